"""Results kept per object between calls (a surface, a polyline): the identity caches of the
incremental rebuild."""
from __future__ import annotations

from typing import Callable, TypeVar

T = TypeVar("T")


def per_object(store: dict, objects: tuple, make: Callable[[], T], extra: tuple = (),
               limit: int = 4096) -> T:
    """make() for these objects (and the hashable `extra`), kept in `store` while they live: keyed
    by their ids, and each entry holds the objects themselves, so an id is not reused by another
    object while its entry is kept. The store is emptied when it holds more than `limit` entries.
    For immutable objects, or ones whose content the result does not outlive."""
    key = tuple(id(o) for o in objects) + tuple(extra)
    entry = store.get(key)
    if entry is None or any(a is not b for a, b in zip(entry[0], objects)):
        if len(store) > limit:
            store.clear()
        entry = store[key] = (objects, make())
    return entry[1]
