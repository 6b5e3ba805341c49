"""One BLAS thread while a build runs.

The fits of a build solve thousands of small systems (core.curve_fit: tens of poles each). A
multi-threaded OpenBLAS hands each to its worker threads, which on a shared or busy machine spend
more time waking and waiting than solving: on the 2-core test machine under load the whole-object
build of vintage_car fitted its curves in 22 s with two BLAS threads and in 10 s with one. Two
threads also split a product differently from one, so the last bits of a result (a fit deviation
of 0.5112290232556859 mm instead of 0.5112290232535821 mm) depended on the thread count; with one
thread a build gives the same numbers every time.

`one_blas_thread` sets an OpenBLAS already loaded in this process (numpy's, found by its exported
`openblas_set_num_threads`) to one thread and restores its count afterwards. Another BLAS, or a
platform where the loaded libraries cannot be listed, is left as it is.
"""
from __future__ import annotations

import ctypes
from contextlib import contextmanager
from functools import lru_cache
from typing import Iterator, Optional


@lru_cache(maxsize=1)
def _openblas() -> Optional[ctypes.CDLL]:
    """The loaded OpenBLAS library (any one of its names: they share one thread pool), or None."""
    import numpy.linalg  # noqa: F401  (loads BLAS and LAPACK)

    try:
        with open("/proc/self/maps", encoding="utf-8", errors="replace") as maps:
            paths = sorted({line.split()[-1] for line in maps
                            if ".so" in line and ("blas" in line or "lapack" in line)})
    except OSError:
        return None
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        if hasattr(lib, "openblas_set_num_threads") and hasattr(lib, "openblas_get_num_threads"):
            return lib
    return None


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """Run the block with OpenBLAS on one thread (module docstring); nested uses are fine."""
    lib = _openblas()
    if lib is None:
        yield
        return
    before = int(lib.openblas_get_num_threads())
    lib.openblas_set_num_threads(1)
    try:
        yield
    finally:
        lib.openblas_set_num_threads(before)
