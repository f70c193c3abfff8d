"""sscape: statistical 3D human body models (S-SCAPE) over the library's C ABI.

    import sscape
    model = sscape.Model()                 # the default model built into the library
    with sscape.Body(model) as body:
        body.shape = [1.0, -0.5]           # standard deviations
        body.set_slider("stature", 1.80)
        print(body.measure()["waist_girth"])
        v = body.vertices                  # (V, 3) float32, metres

Errors raise sscape.SscapeError with the library's status and message.
"""
from ._native import ABI_MAJOR, lib, library_path
from .body import Body, measurement_names, quaternion_from_axis_angle
from .errors import SscapeError
from .fitter import Fitter
from .model import Context, Level, Model, Segment, Slider, default_model_bytes, named_poses
from .registration import Registration

__version__ = "0.1.0"


def library_version() -> str:
    """The loaded libsscape's version, "major.minor.patch"."""
    v = lib.ssc_version()
    return f"{v // 10000}.{v // 100 % 100}.{v % 100}"


__all__ = ["ABI_MAJOR", "Body", "Context", "default_model_bytes", "named_poses", "Fitter", "Level", "Model", "Registration", "Segment", "Slider", "SscapeError", "library_path", "library_version",
           "measurement_names", "quaternion_from_axis_angle", "__version__"]
