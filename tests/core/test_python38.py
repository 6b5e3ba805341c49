"""FreeCAD 0.20 builds run on Python 3.8 and later (package.xml's pythonmin): every module of
ProgSurf, and Init.py / InitGui.py, must parse as Python 3.8 and must not evaluate a PEP 585
(``list[str]``) or PEP 604 (``str | None``) type at run time on 3.8.

This machine has no Python 3.8, so the check is static: ``ast.parse(feature_version=(3, 8))``
for the grammar, and a walk that finds those types where 3.8 would evaluate them: in annotations
of a module without ``from __future__ import annotations``, and anywhere outside annotations
(type aliases, casts, isinstance) in every module.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILTIN_GENERICS = {"list", "dict", "tuple", "set", "frozenset", "type"}
BUILTIN_TYPES = BUILTIN_GENERICS | {"str", "int", "float", "bool", "bytes", "object"}


def sources() -> list[Path]:
    return sorted((ROOT / "ProgSurf").rglob("*.py")) + [ROOT / "Init.py", ROOT / "InitGui.py"]


def _is_new_type(node: ast.AST) -> bool:
    """``list[...]`` (PEP 585) or ``X | None`` / ``str | Y`` (PEP 604)."""
    if isinstance(node, ast.Subscript):
        return isinstance(node.value, ast.Name) and node.value.id in BUILTIN_GENERICS
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.BitOr):
        return any((isinstance(side, ast.Constant) and side.value is None)
                   or (isinstance(side, ast.Name) and side.id in BUILTIN_TYPES)
                   or _is_new_type(side) for side in (node.left, node.right))
    return False


def _annotations(tree: ast.AST) -> list[ast.AST]:
    found = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            args = node.args
            every = args.posonlyargs + args.args + args.kwonlyargs + [args.vararg, args.kwarg]
            found += [a.annotation for a in every if a is not None and a.annotation is not None]
            if node.returns is not None:
                found.append(node.returns)
        elif isinstance(node, ast.AnnAssign):
            found.append(node.annotation)
    return found


def python38_problems(source: str, name: str = "<source>") -> list[str]:
    """What Python 3.8 would reject in ``source``: 'line N: why' for each problem."""
    try:
        tree = ast.parse(source, name, feature_version=(3, 8))
    except SyntaxError as exc:
        return [f"line {exc.lineno}: not Python 3.8 syntax: {exc.msg}"]
    future = any(isinstance(n, ast.ImportFrom) and n.module == "__future__"
                 and any(a.name == "annotations" for a in n.names) for n in tree.body)
    in_annotation = set()
    for annotation in _annotations(tree):
        in_annotation.update(id(n) for n in ast.walk(annotation))
    problems = []
    for node in ast.walk(tree):
        if not _is_new_type(node):
            continue
        if id(node) not in in_annotation:
            problems.append(f"line {node.lineno}: {ast.unparse(node)} is evaluated at run time")
        elif not future:
            problems.append(f"line {node.lineno}: annotation {ast.unparse(node)} needs "
                            "'from __future__ import annotations'")
    return sorted(set(problems))


def test_checker_finds_what_38_rejects():
    assert python38_problems("def f(x: list[str]) -> None: pass")
    assert python38_problems("def f(x: int | None): pass")
    assert python38_problems("from __future__ import annotations\nAlias = dict[str, int]\n")
    assert python38_problems("from __future__ import annotations\n"
                             "import typing\ny = typing.cast(str | None, 1)\n")
    assert python38_problems("match x:\n    case 1:\n        pass\n")
    assert python38_problems("with (open('a') as a, open('b') as b):\n    pass\n")


def test_checker_accepts_what_38_runs():
    assert python38_problems("from __future__ import annotations\n"
                             "def f(x: list[str], y: int | None = None) -> dict[str, int]:\n"
                             "    z: tuple[int, ...] = ()\n    return {}\n") == []
    assert python38_problems("from typing import List, Optional\n"
                             "def f(x: List[str], y: Optional[int]) -> None: pass\n") == []
    assert python38_problems("flags = a | b\nn = (x := 3)\n") == []


@pytest.mark.parametrize("path", sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_module_runs_on_python38(path: Path):
    assert python38_problems(path.read_text(encoding="utf-8"), str(path)) == []
