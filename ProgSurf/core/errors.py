"""The project's one exception family.

Every message names the bad value and says what to do, e.g.
"stroke 7 has 1 point; a stroke needs at least 2".
"""


class ProgSurfError(ValueError):
    """Base of every error ProgSurf raises on purpose."""


class InvalidStrokeError(ProgSurfError):
    """A stroke is malformed: too few points, NaN/inf coordinates, wrong shape."""


class StrokeFileError(ProgSurfError):
    """A stroke file cannot be read: missing, empty, malformed line, unknown format."""


class DegenerateSketchError(ProgSurfError):
    """The sketch has no plane: all points coincident or collinear."""


class OpenBoundaryError(ProgSurfError):
    """The boundary cannot be closed: too few sides, a gap too wide, self-crossing."""


class StrokeOutsideSurfaceError(ProgSurfError):
    """An interior stroke projects outside the current surface; it is rejected."""


class StrokeRejectedError(ProgSurfError):
    """An interior stroke cannot be added for another stated reason."""


class StrokeRunsAlongCurveError(StrokeRejectedError):
    """The pre-image of an interior stroke (or of one of its straight pieces) would run along an
    existing curve. A stroke split into several straight pieces is then tried as one piece."""


class StrokeFoldsError(StrokeRejectedError):
    """An interior stroke would fold the surface (core.folds): a crease or a turned-over face
    that the sketch did not draw, still there after re-planning the regions (core.fold_repair)."""


class FitError(ProgSurfError):
    """OCC could not fit a B-spline curve or face within tolerance."""


class InvalidOptionError(ProgSurfError):
    """An option or tolerance passed by the caller is out of range, e.g. a negative filter threshold."""


class MissingPackageError(ProgSurfError):
    """An optional Python package that a feature needs is not installed (ProgSurf.optional).

    package : the package's import name, e.g. "c3d"
    feature : what needs it, e.g. "reading C3D files"
    The message says how to install it.
    """

    def __init__(self, message: str, package: str, feature: str) -> None:
        super().__init__(message)
        self.package = package
        self.feature = feature
