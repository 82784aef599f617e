"""Timing of libigl's igl.lscm for the comparison in docs/algorithms/lscm.md.

    python crates/lscm/tests/reference/igl_lscm_timing.py /work/shared/meshes

Saddle grids built exactly as in crates/lscm/benches/lscm.rs (z = (x^2 - y^2)/400 over a
200 mm square, same triangulation), pinned at two corners; the real meshes with the boundary
diameter pins of igl_lscm_reference.py. Prints the best of 3 (saddles) / 5 (real) runs.
"""
import os
import sys
import time

import numpy as np
import igl

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from igl_lscm_reference import read_obj  # noqa: E402

folder = sys.argv[1] if len(sys.argv) > 1 else "/work/shared/meshes"
def saddle(n):
    xs = np.linspace(-100, 100, n)
    X, Y = np.meshgrid(xs, xs)
    V = np.stack([X.ravel(), Y.ravel(), (X.ravel()**2 - Y.ravel()**2)/400], 1)
    F = []
    for j in range(n-1):
        for i in range(n-1):
            a, b, c, d = i+n*j, i+1+n*j, i+1+n*(j+1), i+n*(j+1)
            F += [[a,b,c],[a,c,d]]
    return V, np.array(F, dtype=np.int64)
for n in [33, 101, 317]:
    V, F = saddle(n)
    bnd = np.unique(np.concatenate(igl.boundary_loop_all(F)))
    b = np.array([0, n*n-1]); bc = np.array([[0.0,0.0],[np.linalg.norm(V[0]-V[-1]),0.0]])
    ts=[]
    for _ in range(3):
        t=time.perf_counter(); igl.lscm(V,F,b,bc); ts.append(time.perf_counter()-t)
    print(len(F), "faces: igl.lscm min %.4f s" % min(ts))
for name in ["igl_camelhead.obj", "igl_face.obj", "mountain_disk.obj"]:
    V, F = read_obj(f"{folder}/{name}")
    bnd = np.unique(np.concatenate(igl.boundary_loop_all(F)))
    P = V[bnd]; d2 = ((P[:, None, :] - P[None, :, :]) ** 2).sum(-1); k = int(np.argmax(d2))
    i, j = bnd[k // len(bnd)], bnd[k % len(bnd)]
    b = np.array([i, j]); bc = np.array([[0.0, 0.0], [np.linalg.norm(V[i]-V[j]), 0.0]])
    ts = []
    for _ in range(5):
        t = time.perf_counter(); igl.lscm(V, F, b, bc); ts.append(time.perf_counter() - t)
    print(name, len(F), "faces: igl.lscm min %.4f s median %.4f s" % (min(ts), sorted(ts)[2]))
