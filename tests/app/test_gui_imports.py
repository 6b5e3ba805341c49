"""The GUI layer imports without cycles: no ProgSurf.gui module imports another that imports it
back, directly or through others, also not inside a function (STYLE.md: GUI helpers live in one
small module, ProgSurf.gui.common, that every GUI module may import).

Pure Python: the modules are parsed with `ast`, never imported. unittest classes, so that both
pytest and `freecadcmd -t TestProgSurfApp` run them.
"""
import ast
import unittest
from pathlib import Path

GUI = Path(__file__).resolve().parents[2] / "ProgSurf" / "gui"
PACKAGE = "ProgSurf.gui"
INIT = "__init__"


def gui_imports(source: str, modules: set[str]) -> set[str]:
    """The sibling GUI modules (names in `modules`, `__init__` for the package itself) that
    `source` imports anywhere: at the top, inside functions and inside classes."""
    found = set()

    def add(dotted: str) -> None:
        # dotted is relative to the package: "" (the package), "commands", "commands.x", ...
        head = dotted.split(".", 1)[0]
        found.add(head if head in modules else INIT)

    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == PACKAGE or alias.name.startswith(PACKAGE + "."):
                    add(alias.name[len(PACKAGE) + 1:])
        elif isinstance(node, ast.ImportFrom):
            if node.level == 1:
                base = node.module or ""
            elif node.level == 0 and node.module and (
                    node.module == PACKAGE or node.module.startswith(PACKAGE + ".")):
                base = node.module[len(PACKAGE) + 1:]
            else:
                continue
            if base:
                add(base)
            else:  # from . import a, b: each name is a module, or a name of the package
                for alias in node.names:
                    add(alias.name)
    return found


def gui_import_graph(folder: Path = GUI) -> dict[str, set[str]]:
    """{module: the sibling modules it imports} for every .py file of the GUI package."""
    sources = {path.stem: path.read_text(encoding="utf-8") for path in folder.glob("*.py")}
    modules = set(sources)
    return {name: gui_imports(text, modules) - {name} for name, text in sources.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str]:
    """One import cycle as [a, b, ..., a], or [] when the graph has none (depth-first search)."""
    state: dict[str, int] = {}          # 1 = on the current path, 2 = done
    path: list[str] = []

    def visit(node: str) -> list[str]:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        path.pop()
        state[node] = 2
        return []

    for start in sorted(graph):
        if start not in state:
            cycle = visit(start)
            if cycle:
                return cycle
    return []


class TestGuiImportGraph(unittest.TestCase):

    def test_checker_sees_imports_inside_functions(self):
        modules = {"a", "b", "c", INIT}
        source = ("import os\n"
                  "from .a import x\n"
                  "def f():\n"
                  "    from . import b\n"
                  "    import ProgSurf.gui.c\n"
                  "    from ProgSurf.gui import y\n"
                  "    from ProgSurf.app import make\n")
        self.assertEqual(gui_imports(source, modules), {"a", "b", "c", INIT})

    def test_checker_finds_a_cycle(self):
        self.assertEqual(find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}), ["a", "b", "c", "a"])
        self.assertEqual(find_cycle({"a": {"b", "c"}, "b": {"c"}, "c": set()}), [])

    def test_gui_modules_import_without_cycles(self):
        graph = gui_import_graph()
        self.assertIn("commands", graph)
        self.assertEqual(find_cycle(graph), [], f"GUI import graph: {graph}")


if __name__ == "__main__":
    unittest.main()
