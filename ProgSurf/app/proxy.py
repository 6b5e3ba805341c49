"""What every ProgSurf FeaturePython proxy shares: it attaches to its object, (re)creates the
object's properties, and saves a tiny JSON-safe state (STYLE.md).

A document's truth lives in typed FreeCAD properties; the proxy saves only its type and a format
version. FreeCAD 0.20.2 with Python 3.11 calls ``__getstate__`` / ``__setstate__``; later
versions call ``dumps`` / ``loads``: both are supported here, once for every proxy.
"""
from __future__ import annotations

PROP_OUTPUT = 8
"""App::Property::Output: a change does not mark the object touched (FreeCAD PropertyType)."""


def add_property(obj, kind: str, name: str, group: str, doc: str, attr: int = 0,
                 read_only=False) -> None:
    """Add property ``name`` unless the object has it (documents saved by older versions)."""
    if name not in obj.PropertiesList:
        obj.addProperty(kind, name, group, doc, attr)
    if read_only:
        obj.setEditorMode(name, 1)


class FeatureProxy:
    """Base of the proxies of Part::FeaturePython objects; ``PROXY_TYPE`` is the object's
    ``Type`` ("ProgSurf::..."). A subclass extends ``setup`` with its own properties; one with
    transient data resets it in ``__setstate__`` (a document was read)."""

    PROXY_TYPE = ""

    def __init__(self, obj) -> None:
        obj.Proxy = self
        self.Object = obj
        self.setup(obj)

    def setup(self, obj) -> None:
        """Create missing properties (new objects and documents saved by older versions)."""
        add_property(obj, "App::PropertyString", "Type", "Base", "ProgSurf object type",
                     read_only=True)
        obj.Type = self.PROXY_TYPE

    def onDocumentRestored(self, obj) -> None:
        self.Object = obj
        self.setup(obj)

    def __getstate__(self) -> dict:
        return {"type": self.PROXY_TYPE, "version": 1}

    def __setstate__(self, state) -> None:
        return None

    def dumps(self) -> dict:
        return self.__getstate__()

    def loads(self, state) -> None:
        return self.__setstate__(state)
