"""Rendered images: linear RGB and AOVs as numpy arrays."""

import os

import numpy as np

from . import _appel

#: AOVs a render can return (``variance`` only from the Monte Carlo integrators).
AOV_NAMES = ("depth", "normal", "shapeid", "primid", "instanceid", "variance")


class Image:
    """A rendered image.

    ``rgb`` is linear float32 of shape (H, W, 3); ``aovs`` maps AOV names to arrays: ``depth``
    (H, W) float32 (inf on a miss), ``normal`` (H, W, 3) float32, ``shapeid``, ``primid`` and
    ``instanceid`` (H, W) uint32 (4294967295 on a miss), ``variance`` (H, W, 3) float32.
    """

    def __init__(self, rgb, aovs=None):
        self.rgb = rgb
        self.aovs = dict(aovs or {})

    @property
    def width(self):
        return self.rgb.shape[1]

    @property
    def height(self):
        return self.rgb.shape[0]

    def save(self, path):
        """Writes ``.png`` (8-bit sRGB) or ``.exr`` (float RGB and every AOV of the image) as
        ``appel render`` does, atomically."""
        rgb = np.ascontiguousarray(self.rgb, dtype=np.float32)
        aovs = {k: np.ascontiguousarray(v) for k, v in self.aovs.items()}
        _appel.save_image(os.fspath(path), rgb, aovs)

    def _repr_png_(self):
        return _appel.png_bytes(np.ascontiguousarray(self.rgb, dtype=np.float32))

    def __repr__(self):
        names = ", ".join(self.aovs) or "no AOVs"
        return f"<appel.Image {self.width}x{self.height}, {names}>"


def aov_set(aovs):
    """The AOV names asked for, checked; ``primid`` brings ``shapeid``, as on the command line."""
    if isinstance(aovs, str):
        aovs = [a for a in aovs.split(",") if a.strip()]
    names = []
    for a in aovs:
        a = a.strip()
        if a not in AOV_NAMES:
            raise ValueError(f"aovs: unknown AOV {a!r}, expected some of: {', '.join(AOV_NAMES)}")
        if a not in names:
            names.append(a)
    if "primid" in names and "shapeid" not in names:
        names.append("shapeid")
    return names


def image_from(arrays, aovs):
    """An Image of the native render's arrays, keeping the AOVs asked for."""
    out = {}
    for a in aovs:
        if a not in arrays:
            raise ValueError("aovs: variance needs a Monte Carlo integrator (path or direct)")
        out[a] = arrays[a]
    return Image(arrays["rgb"], out)
