#!/usr/bin/python3
"""Runs Siconos (Debian's python3-siconos) on FCLib files as they are written
(a local problem, or a global one condensed by NumPy: W = H^T M^-1 H,
q = H^T M^-1 f + w, a matrix stored as one triangle completed by symmetry),
and prints one JSON line per (file, solver): time, Siconos' own error
(fc3d's), and the natural-map residual of `signorini local` (forces relative
to max(max|q| / max diag W, max|r|), gaps to max|q|), so that both are judged
alike; then, with --signorini BIN, `BIN local FILE` on the same file, its
time and the Siconos error of its forces.

Usage: OPENBLAS_NUM_THREADS=1 /usr/bin/python3 docs/peers/siconos_fclib.py FILE.hdf5...
       [--tol 1e-10] [--solvers NSGS,NSN_AC,VI_EG] [--signorini target/release/signorini]
"""
import json
import os
import subprocess
import sys
import time

import h5py
import numpy as np
import siconos.numerics as sn

# The FCLib matrix reader of the test data's generator (one reader of the
# format for both).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../tests/data/fclib"))
from make_fclib import dense  # noqa: E402


def symmetric_if_triangle(a):
    """A square matrix with one strictly empty triangle is symmetric stored as
    the other: completed."""
    if a.shape[0] == a.shape[1] and a.shape[0] > 1:
        lower, upper = np.tril(a, -1), np.triu(a, 1)
        if not lower.any() and upper.any():
            return a + upper.T
        if not upper.any() and lower.any():
            return a + lower.T
    return a


def read(path):
    with h5py.File(path, "r") as f:
        if "fclib_global" in f:
            g = f["fclib_global"]
            m, h = symmetric_if_triangle(dense(g["M"])), dense(g["H"])
            fv, w, mu = g["vectors/f"][()], g["vectors/w"][()], g["vectors/mu"][()]
            x = np.linalg.solve(m, np.column_stack([h, fv]))
            return int(g["spacedim"][0]), h.T @ x[:, :-1], h.T @ x[:, -1] + w, mu
        loc = f["fclib_local"]
        w = symmetric_if_triangle(dense(loc["W"]))
        return int(loc["spacedim"][0]), w, loc["vectors/q"][()], loc["vectors/mu"][()]


def residual(w, q, mu, dim, r):
    """signorini's natural-map residual: normal min(λ_n/F, g_n/L), tangential
    |λ_t - proj_{μλ_n}(λ_t - (F/L) g_t)| / F."""
    g = w @ r + q
    qmax = max(np.abs(q).max(), 1e-300)
    f = max(qmax / max(np.abs(np.diag(w)).max(), 1e-300), np.abs(r).max())
    r3, g3 = r.reshape(-1, dim), g.reshape(-1, dim)
    res = np.abs(np.minimum(r3[:, 0] / f, g3[:, 0] / qmax)).max(initial=0.0)
    trial = r3[:, 1:] - f / qmax * g3[:, 1:]
    radius = mu * np.maximum(r3[:, 0], 0.0)
    norm = np.linalg.norm(trial, axis=1)
    scale = np.where(norm > radius, radius / np.maximum(norm, 1e-300), 1.0)
    res = max(res, (np.abs(r3[:, 1:] - trial * scale[:, None]) / f).max(initial=0.0))
    return res


def siconos(dim, w, q, mu, solver, tol, max_s):
    n = len(q)
    prefix = "SICONOS_FRICTION_2D_" if dim == 2 else "SICONOS_FRICTION_3D_"
    so = sn.SolverOptions(getattr(sn, prefix + solver))
    so.dparam[sn.SICONOS_DPARAM_TOL] = tol
    so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 100000
    r, u = np.zeros(n), np.zeros(n)
    driver = sn.fc2d_driver if dim == 2 else sn.fc3d_driver
    p = sn.FrictionContactProblem(dim, n // dim, w, q, mu)
    t = time.perf_counter()
    info = driver(p, r, u, so)
    return r, info, time.perf_counter() - t, so.dparam[sn.SICONOS_DPARAM_RESIDU]


def fc3d_error(dim, w, q, mu, r):
    if dim != 3:
        return None
    p = sn.FrictionContactProblem(dim, len(q) // dim, w, q, mu)
    u = w @ r + q
    return sn.fc3d_compute_error(p, r, u, 1e-10, sn.SolverOptions(sn.SICONOS_FRICTION_3D_NSGS), np.linalg.norm(q))[1]


def main():
    args, files = sys.argv[1:], []
    tol, solvers, binary = 1e-10, ["NSGS", "NSN_AC", "VI_EG"], None
    while args:
        a = args.pop(0)
        if a == "--tol":
            tol = float(args.pop(0))
        elif a == "--solvers":
            solvers = args.pop(0).split(",")
        elif a == "--signorini":
            binary = args.pop(0)
        else:
            files.append(a)
    for path in files:
        dim, w, q, mu = read(path)
        line = {"file": path, "m": len(q) // dim, "rank": int(np.linalg.matrix_rank(w)),
                "rows": len(q), "asymmetry": float(np.abs(w - w.T).max() / np.abs(w).max())}
        print(json.dumps(line), flush=True)
        for s in solvers:
            r, info, t, err = siconos(dim, w, q, mu, s, tol, 60)
            print(json.dumps({"file": path, "solver": s, "info": info, "time_s": t, "siconos_error": err,
                              "signorini_residual": residual(w, q, mu, dim, r)}), flush=True)
        if binary:
            t = time.perf_counter()
            out = subprocess.run([binary, "local", path, "--lambda"], capture_output=True, text=True)
            wall = time.perf_counter() - t
            v = json.loads(out.stdout) if out.stdout else {}
            r = np.array(v.get("lambda", np.zeros(len(q))))
            print(json.dumps({"file": path, "solver": "signorini " + v.get("method", "?"), "exit": out.returncode,
                              "time_s": v.get("time_s"), "wall_s": wall, "residual": v.get("residual"),
                              "siconos_error": fc3d_error(dim, w, q, mu, r),
                              "signorini_residual": residual(w, q, mu, dim, r)}), flush=True)


if __name__ == "__main__":
    main()
