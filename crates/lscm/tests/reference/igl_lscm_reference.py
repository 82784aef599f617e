"""Reference numbers for crates/lscm/tests/real_meshes.rs, computed with libigl's igl.lscm.

Run (libigl's Python package, `pip install libigl numpy`; produced with libigl 2.6.x from
PyPI, numpy 2.x):

    python crates/lscm/tests/reference/igl_lscm_reference.py /work/shared/meshes

For each mesh: parse the OBJ (v / f lines, triangles only, 1-based), pick the two pins as
the pair of boundary vertices farthest apart in 3D (exact O(b^2) diameter; ties broken by
the smallest (i, j) index pair in numpy's argmax order), pin them at (0, 0) and (d, 0)
with d their 3D distance, run igl.lscm, and measure per triangle the singular values
s1 >= s2 of the 3D->2D affine map (via numpy's SVD of the 2x2 Jacobian in the triangle's
own frame):  E_r = 1 - s2/s1,  E_h = |s1*s2 - 1|, and their area-weighted means over
faces (weights = 3D triangle areas). Also prints x^T Q x with libigl's returned Q
(Q = -L - 2A in libigl's conventions, so x^T Q x = 2 E_C, twice flatcut's conformal energy).
"""

import sys
import time

import numpy as np
import igl


def read_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                assert len(idx) == 3, "triangles only"
                f.append(idx)
    return np.array(v, dtype=np.float64), np.array(f, dtype=np.int64)


def metrics(V, F, uv):
    p0, p1, p2 = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    e1, e2 = p1 - p0, p2 - p0
    n = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(n, axis=1)
    x = e1 / np.linalg.norm(e1, axis=1)[:, None]
    y = np.cross(n, e1)
    y /= np.linalg.norm(y, axis=1)[:, None]
    # Q: columns are the frame coordinates of the two edges; U: their uv images.
    Q = np.stack([np.stack([np.linalg.norm(e1, axis=1), np.zeros(len(F))], 1),
                  np.stack([(e2 * x).sum(1), (e2 * y).sum(1)], 1)], 2)
    U = np.stack([uv[F[:, 1]] - uv[F[:, 0]], uv[F[:, 2]] - uv[F[:, 0]]], 2)
    J = U @ np.linalg.inv(Q)
    s = np.linalg.svd(J, compute_uv=False)
    e_r = 1.0 - s[:, 1] / s[:, 0]
    e_h = np.abs(s[:, 0] * s[:, 1] - 1.0)
    w = area / area.sum()
    return (w * e_r).sum(), (w * e_h).sum(), e_r.max()


def main(folder):
    for name in ["igl_camelhead.obj", "igl_face.obj"]:
        V, F = read_obj(f"{folder}/{name}")
        bnd = np.unique(np.concatenate(igl.boundary_loop_all(F)))
        P = V[bnd]
        d2 = ((P[:, None, :] - P[None, :, :]) ** 2).sum(-1)
        k = int(np.argmax(d2))
        i, j = bnd[k // len(bnd)], bnd[k % len(bnd)]
        i, j = min(i, j), max(i, j)
        d = np.linalg.norm(V[i] - V[j])
        b = np.array([i, j], dtype=np.int64)
        bc = np.array([[0.0, 0.0], [d, 0.0]])
        t = time.perf_counter()
        uv, Qm = igl.lscm(V, F, b, bc)
        secs = time.perf_counter() - t
        x = uv.T.reshape(-1)  # libigl orders unknowns (all u, then all v)
        energy = x @ (Qm @ x)
        mean_er, mean_eh, max_er = metrics(V, F, uv)
        print(f"{name}: V={len(V)} F={len(F)} pins=({i}, {j}) d={d:.17g}")
        print(f"  mean_E_r={mean_er:.17g} mean_E_h={mean_eh:.17g} max_E_r={max_er:.17g}")
        print(f"  xQx={energy:.17g} igl.lscm seconds={secs:.3f}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "/work/shared/meshes")
