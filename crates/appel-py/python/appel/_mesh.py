"""Triangle meshes from numpy arrays, checked before they reach the library."""

import numpy as np


def _floats(name, x, columns, rows=None):
    if isinstance(x, np.ndarray):
        if x.dtype not in (np.float32, np.float64):
            raise ValueError(f"{name}: expected float32 or float64, got {x.dtype}")
    else:
        try:
            x = np.asarray(x, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise ValueError(f"{name}: expected an array of numbers ({e})") from None
    if x.ndim != 2 or x.shape[1] != columns:
        raise ValueError(f"{name}: expected shape (N, {columns}), got {x.shape}")
    if rows is not None and x.shape[0] != rows:
        raise ValueError(f"{name}: expected {rows} rows (one per vertex), got {x.shape[0]}")
    if not np.isfinite(x).all():
        bad = int(np.argwhere(~np.isfinite(x))[0][0])
        raise ValueError(f"{name}: row {bad} is not finite (NaN or infinite)")
    return np.ascontiguousarray(x, dtype=np.float32)


class Mesh:
    """A triangle mesh: ``vertices`` (N, 3) float32 or float64, ``indices`` (M, 3) of any integer
    dtype, optional per-vertex ``normals`` (N, 3) and ``uvs`` (N, 2). Wrong shapes, NaNs and
    out-of-range indices raise ValueError naming the argument."""

    def __init__(self, vertices, indices, normals=None, uvs=None):
        self.vertices = _floats("vertices", vertices, 3)
        n = self.vertices.shape[0]
        i = indices if isinstance(indices, np.ndarray) else np.asarray(indices)
        if i.size == 0 and i.dtype == np.float64:
            i = i.astype(np.int64)
        if not np.issubdtype(i.dtype, np.integer):
            raise ValueError(f"indices: expected an integer dtype, got {i.dtype}")
        if i.ndim != 2 or i.shape[1] != 3:
            raise ValueError(f"indices: expected shape (M, 3), got {i.shape}")
        if i.size:
            lo, hi = int(i.min()), int(i.max())
            if lo < 0 or hi >= n:
                bad = lo if lo < 0 else hi
                row = int(np.argwhere((i < 0) | (i >= n))[0][0])
                raise ValueError(
                    f"indices: row {row} has index {bad}, out of range for {n} vertices"
                )
        self.indices = np.ascontiguousarray(i, dtype=np.uint32)
        self.normals = None if normals is None else _floats("normals", normals, 3, n)
        self.uvs = None if uvs is None else _floats("uvs", uvs, 2, n)

    @property
    def triangle_count(self):
        return self.indices.shape[0]

    def _native(self):
        return (self.vertices, self.indices, self.normals, self.uvs)

    def __repr__(self):
        return f"<appel.Mesh {self.vertices.shape[0]} vertices, {self.triangle_count} triangles>"
