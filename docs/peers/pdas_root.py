#!/usr/bin/python3
"""A plain primal-dual active set method (PDAS) in NumPy on the LCPs that
`signorini bench --suite root --export DIR` writes, timed in the same run as
`signorini local` on the same files (alternating, problem by problem), so
that a loaded machine slows both alike.

PDAS on LCP(W, q): λ ≥ 0, g = W λ + q ≥ 0, λ·g = 0. From λ = 0 (g = q):
A = {i : λ_i − c g_i > 0} (c = 1 / mean diag W), λ_I = 0 and W_AA λ_A = −q_A
by a Cholesky factorisation of W_AA (LAPACK potrf through numpy/scipy, the
BLAS the machine's numpy is linked to), g = W λ + q, until A repeats.
Frictional files (dim > 1) are skipped.

Each line of output is one JSON record: the problem, the peer ("numpy_pdas"
or "signorini"), the method, iterations, the active points, wall time
(median of --repeat runs), CPU time (user + sys of this process for numpy;
signorini's wall time only, it reports no CPU time), and the residual in
signorini's measure (scaled natural map, docs/peers/siconos_root.py).

Usage: /usr/bin/python3 docs/peers/pdas_root.py DIR/*.npz [--repeat 5]
       [--signorini target/release/signorini] [--method status] [--tol 1e-10]
"""
import json
import os
import subprocess
import sys
import time

import numpy as np
import scipy.linalg as sl


def residual(w, q, lam):
    """max |min(λ / F, g / L)|, F = max(max|q| / max diag W, max|λ|), L = max|q|."""
    g = w @ lam + q
    qmax = max(np.abs(q).max(), 1e-300)
    f = max(qmax / max(np.abs(np.diag(w)).max(), 1e-300), np.abs(lam).max())
    return float(np.abs(np.minimum(lam / f, g / qmax)).max(initial=0.0))


def pdas(w, q, tol, max_iter=200):
    """Returns (λ, iterations, converged)."""
    m = len(q)
    c = 1.0 / np.mean(np.diag(w))
    lam, g = np.zeros(m), q.copy()
    active = None
    for it in range(1, max_iter + 1):
        new = lam - c * g > tol * max(np.abs(q).max(), 1e-300) * c
        if active is not None and np.array_equal(new, active):
            return lam, it - 1, True
        active = new
        idx = np.flatnonzero(active)
        lam = np.zeros(m)
        if len(idx):
            factor = sl.cho_factor(w[np.ix_(idx, idx)], lower=True, check_finite=False)
            lam[idx] = sl.cho_solve(factor, -q[idx], check_finite=False)
        g = w @ lam + q
    return lam, max_iter, False


def time_pdas(w, q, tol, repeat):
    walls, cpus = [], []
    for _ in range(repeat):
        t, c = time.perf_counter(), os.times()
        lam, its, ok = pdas(w, q, tol)
        c2 = os.times()
        walls.append(time.perf_counter() - t)
        cpus.append((c2.user - c.user) + (c2.system - c.system))
    return lam, its, ok, float(np.median(walls)), float(np.median(cpus))


def time_signorini(exe, path, method, tol, repeat):
    out = subprocess.run(
        [exe, "local", path, "--method", method, "--tolerance", str(tol),
         "--repeat", str(repeat)],
        capture_output=True, text=True, check=False,
    )
    line = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else "{}"
    return out.returncode, json.loads(line)


def main():
    args = sys.argv[1:]

    def opt(name, default):
        return args[args.index(name) + 1] if name in args else default

    repeat = int(opt("--repeat", "5"))
    tol = float(opt("--tol", "1e-10"))
    exe = opt("--signorini", "target/release/signorini")
    method = opt("--method", "status")
    files = [a for a in args if a.endswith(".npz")]
    for path in files:
        d = np.load(path)
        if int(d["dim"]) != 1:
            continue
        w, q = np.ascontiguousarray(d["W"]), d["q"].copy()
        code, s = time_signorini(exe, path, method, tol, repeat)
        print(json.dumps({
            "problem": path, "peer": "signorini", "method": method, "m": len(q),
            "exit": code, "converged": s.get("converged"), "iterations": s.get("iterations"),
            "time_s": s.get("time_s"), "residual": s.get("residual"),
        }), flush=True)
        lam, its, ok, wall, cpu = time_pdas(w, q, tol, repeat)
        print(json.dumps({
            "problem": path, "peer": "numpy_pdas", "method": "pdas", "m": len(q),
            "converged": ok, "iterations": its, "active": int((lam > 0).sum()),
            "time_s": wall, "cpu_s": cpu, "residual": residual(w, q, lam),
        }), flush=True)


if __name__ == "__main__":
    main()
