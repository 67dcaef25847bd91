"""EXR reading and error measures for bench/peers (Mitsuba's Bitmap reads EXR)."""

import numpy as np

_mi = None


def _mitsuba():
    global _mi
    if _mi is None:
        import mitsuba as mi
        if mi.variant() is None:
            mi.set_variant("scalar_rgb")
        _mi = mi
    return _mi


def read_exr(path):
    """Linear RGB as float64, shape (height, width, 3)."""
    mi = _mitsuba()
    b = mi.Bitmap(str(path))
    a = np.array(b, dtype=np.float64)
    if a.ndim == 2:
        a = a[:, :, None]
    return a[:, :, :3]


def rmse(img, ref):
    """Root mean square over every pixel and channel."""
    return float(np.sqrt(np.mean((img - ref) ** 2)))


def brightness_ratio(img, ref):
    return float(img.mean() / ref.mean())
