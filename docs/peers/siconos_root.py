#!/usr/bin/python3
"""Runs Siconos (Debian's python3-siconos) on the stand-alone problems that
`signorini bench --suite root --export DIR` writes (W, q, mu, dim in the
contact-wise layout), and prints one JSON line per (problem, solver): time,
Siconos' own error, and the residual signorini reports (scaled natural map of
the normal rows plus the cone violation), so that both are judged alike.

Usage: /usr/bin/python3 docs/peers/siconos_root.py DIR/*.npz [--tol 1e-10] [--max-s 60]
       [--solvers NEWTON_MIN_FBLSA,VI_EG]   (only these; default: every solver listed below)
Single-threaded BLAS: run with OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1.
"""
import json
import sys
import time

import numpy as np
import siconos.numerics as sn

LCP = ["LEMKE", "NEWTON_MIN_FBLSA", "NEWTON_FB_FBLSA", "PGS", "CPG"]
FC2D = ["CPG", "NSGS", "LEMKE"]
FC3D = ["NSGS", "VI_EG", "NSN_AC", "VI_FPP", "PROX"]
# Pivoting solvers skipped above these sizes (minutes each).
SLOW = {"LEMKE": 1000}


def residual(w, q, mu, dim, r):
    """max over contacts of |min(λ_n/F, g_n/L)| and the cone violation / F,
    F = max|q| / max diag W, L = max|q| (signorini local's scales)."""
    g = w @ r + q
    qmax = max(np.abs(q).max(), 1e-300)
    f = max(qmax / max(np.abs(np.diag(w)).max(), 1e-300), np.abs(r).max())
    rn, gn = r[0::dim], g[0::dim]
    res = np.abs(np.minimum(rn / f, gn / qmax)).max(initial=0.0)
    if dim > 1 and len(mu):
        rt = r.reshape(-1, dim)[:, 1:]
        cone = np.linalg.norm(rt, axis=1) - mu * np.maximum(rn, 0.0)
        res = max(res, np.maximum(cone, 0.0).max(initial=0.0) / f)
    return res


def solve(w, q, mu, dim, name, tol, max_iter):
    n = len(q)
    r, u = np.zeros(n), np.zeros(n)
    if dim == 1 or len(mu) == 0:
        m = n // dim
        wn, qn = w[0::dim, 0::dim].copy(), q[0::dim].copy()
        so = sn.SolverOptions(getattr(sn, "SICONOS_LCP_" + name))
        so.dparam[sn.SICONOS_DPARAM_TOL] = tol
        so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = max_iter
        z, v = np.zeros(m), np.zeros(m)
        t = time.perf_counter()
        info = sn.linearComplementarity_driver(sn.LCP(wn, qn), z, v, so)
        dt = time.perf_counter() - t
        r[0::dim] = z
    else:
        prefix = "SICONOS_FRICTION_2D_" if dim == 2 else "SICONOS_FRICTION_3D_"
        so = sn.SolverOptions(getattr(sn, prefix + name))
        so.dparam[sn.SICONOS_DPARAM_TOL] = tol
        so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = max_iter
        problem = sn.FrictionContactProblem(dim, n // dim, w, q, mu)
        driver = sn.fc2d_driver if dim == 2 else sn.fc3d_driver
        t = time.perf_counter()
        info = driver(problem, r, u, so)
        dt = time.perf_counter() - t
    return info, dt, so.dparam[sn.SICONOS_DPARAM_RESIDU], so.iparam[sn.SICONOS_IPARAM_ITER_DONE], r


def main():
    args = sys.argv[1:]
    tol, max_s = 1e-10, 60.0
    if "--tol" in args:
        tol = float(args[args.index("--tol") + 1])
    if "--max-s" in args:
        max_s = float(args[args.index("--max-s") + 1])
    only = None
    if "--solvers" in args:
        only = set(args[args.index("--solvers") + 1].split(","))
    files = [a for a in args if a.endswith(".npz")]
    for path in files:
        d = np.load(path)
        w, q, dim = d["W"], d["q"], int(d["dim"])
        mu = d["mu"] if "mu" in d else np.zeros(0)
        names = LCP if dim == 1 or len(mu) == 0 else (FC2D if dim == 2 else FC3D)
        for name in names:
            if only is not None and name not in only:
                continue
            if name in SLOW and len(q) // dim > SLOW[name]:
                print(json.dumps({"problem": path, "solver": name, "note": "skipped: pivoting, too slow at this size"}))
                continue
            try:
                info, dt, err, it, r = solve(w, q, mu, dim, name, tol, 100000)
            except Exception as e:  # a solver Siconos lacks for this problem
                print(json.dumps({"problem": path, "solver": name, "error": str(e)}))
                continue
            print(json.dumps({
                "problem": path, "peer": "siconos", "solver": name, "m": len(q) // dim,
                "dim": dim, "converged": info == 0, "iterations": int(it), "time_s": dt,
                "siconos_error": err, "residual": residual(w, q, mu, dim, r),
            }), flush=True)
            if dt > max_s:
                print(json.dumps({"problem": path, "solver": name, "note": "slow: larger sizes skipped"}))


if __name__ == "__main__":
    main()
