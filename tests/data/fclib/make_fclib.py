#!/usr/bin/python3
"""Writes the FCLib test files of tests/integration/fclib.rs into this directory.

1. Builds make_fclib.c (the FCLib C library, Debian's libfclib-dev) and runs
   it: the problems are written by fclib_write_local / fclib_write_global.
2. Reads each local problem back with h5py (a reader independent of both
   FCLib and signorini), solves it with Siconos (Debian's python3-siconos:
   fc2d / fc3d NSGS to 1e-14), checks Siconos' forces against the problem's
   manufactured solution, and stores Siconos' r and u as the file's
   /solution through fclib_write_solution.
2b. Each global problem likewise: condensed by NumPy (W = H^T M^-1 H,
   q = H^T M^-1 f + w, dense solves; with equality constraints G, b, by
   dense solves of the KKT matrix [M G; G^T 0]), solved by Siconos' fc2d / fc3d NSGS on
   that and, in 3D without G, by Siconos' own global solver (gfc3d, nonsmooth Newton
   Alart-Curnier on M, H, f, w, no condensation) as a cross-check; its r, u
   and v = M^-1 (H r + f) are stored as /solution, and NumPy's W and q as
   NAME_condensed.npz (W, q, mu, dim: a local problem `signorini local`
   reads) for tests/integration/fclib.rs to compare with its own condensation.
3. Copies the 3D problem into a file in HDF5's newest format (h5py,
   libver='latest': superblock v3, link messages, v2 object headers; its
   arrays chunked and deflated).
4. Writes broken copies (bad_*.hdf5) for the refusals of `signorini local`.

Usage: /usr/bin/python3 tests/data/fclib/make_fclib.py   (not the pyenv python3)
Needs Debian's libfclib-dev, libhdf5-dev, python3-siconos, python3-h5py, gcc.
A rerun writes the same data; the bytes differ (libhdf5 stores the time of
writing in each dataset's header).
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np
import siconos.numerics as sn

HERE = os.path.dirname(os.path.abspath(__file__))
LOCAL = ["fc2d_triplet.hdf5", "fc3d_csc.hdf5", "fc3d_csr.hdf5"]
GLOBAL = ["global2d.hdf5", "global3d.hdf5", "global3d_g.hdf5"]


def build(tmp):
    exe = os.path.join(tmp, "make_fclib")
    flags = subprocess.check_output(["pkg-config", "--cflags", "--libs", "fclib"], text=True).split()
    subprocess.check_call(["gcc", "-O2", "-Wall", "-o", exe, os.path.join(HERE, "make_fclib.c")] + flags + ["-lm"])
    return exe


def dense(g):
    """W of an FCLib matrix group, duplicates summed (CSparse's triplets: i rows, p columns)."""
    m, n, nz = int(g["m"][0]), int(g["n"][0]), int(g["nz"][0])
    p, i, x = g["p"][()], g["i"][()], g["x"][()]
    w = np.zeros((m, n))
    if nz >= 0:
        np.add.at(w, (i[:nz], p[:nz]), x[:nz])
    else:
        outer = n if nz == -1 else m
        for a in range(outer):
            for k in range(p[a], p[a + 1]):
                if nz == -1:
                    w[i[k], a] += x[k]
                else:
                    w[a, i[k]] += x[k]
    return w


def siconos_local(d, w, q, mu):
    """Siconos' fc2d / fc3d NSGS on u = W r + q, to 1e-14."""
    n = len(q)
    prefix = "SICONOS_FRICTION_2D_" if d == 2 else "SICONOS_FRICTION_3D_"
    so = sn.SolverOptions(getattr(sn, prefix + "NSGS"))
    so.dparam[sn.SICONOS_DPARAM_TOL] = 1e-14
    so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 100000
    r, u = np.zeros(n), np.zeros(n)
    driver = sn.fc2d_driver if d == 2 else sn.fc3d_driver
    info = driver(sn.FrictionContactProblem(d, n // d, w, q, mu), r, u, so)
    err = so.dparam[sn.SICONOS_DPARAM_RESIDU]
    assert info == 0 and err < 1e-13, (info, err)
    return r, u, err


def siconos_solve(path):
    with h5py.File(path, "r") as f:
        loc = f["fclib_local"]
        d = int(loc["spacedim"][0])
        w, q, mu = dense(loc["W"]), loc["vectors/q"][()], loc["vectors/mu"][()]
    return siconos_local(d, w, q, mu)


def siconos_global_3d(m, h, f, w, mu):
    """Siconos' global solver (gfc3d, nonsmooth Newton Alart-Curnier on the
    global problem itself): r, v."""
    p = sn.GlobalFrictionContactProblem()
    p.dimension, p.numberOfContacts = 3, len(mu)
    p.M, p.H, p.q, p.b, p.mu = m, h, f, w, mu
    so = sn.SolverOptions(sn.SICONOS_GLOBAL_FRICTION_3D_NSN_AC)
    so.dparam[sn.SICONOS_DPARAM_TOL] = 1e-14
    so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 1000
    r, u, v = np.zeros(len(w)), np.zeros(len(w)), np.zeros(len(f))
    info = sn.gfc3d_driver(p, r, u, v, so)
    assert info == 0, info
    return r, v


def solve_global(path, manufactured):
    """Condenses a global problem with NumPy, solves it with Siconos, writes
    NAME_condensed.npz and returns r, u, v and a summary line."""
    with h5py.File(path, "r") as g:
        gl = g["fclib_global"]
        d = int(gl["spacedim"][0])
        m, h = dense(gl["M"]), dense(gl["H"])
        f, w, mu = gl["vectors/f"][()], gl["vectors/w"][()], gl["vectors/mu"][()]
        gm = dense(gl["G"]) if "G" in gl else np.zeros((len(f), 0))
        b = gl["vectors/b"][()] if "G" in gl else np.zeros(0)
    n, p = gm.shape
    # With equality constraints: v solves [M G; G^T 0] [v; -lambda] = [H r + f; -b].
    kkt = np.block([[m, gm], [gm.T, np.zeros((p, p))]])
    solve_v = lambda rhs, rhs_b: np.linalg.solve(kkt, np.concatenate([rhs, rhs_b]))[:n]
    wm = h.T @ np.column_stack([solve_v(h[:, j], np.zeros(p)) for j in range(h.shape[1])])
    wm = 0.5 * (wm + wm.T)
    q = h.T @ solve_v(f, -b) + w
    np.savez(path.replace(".hdf5", "_condensed.npz"), W=wm, q=q, mu=mu, dim=np.array(d))
    r, u, err = siconos_local(d, wm, q, mu)
    v = solve_v(h @ r + f, -b)
    r0, u0, v0 = manufactured
    gap = max(np.abs(r - r0).max() / np.abs(r0).max(), np.abs(v - v0).max() / np.abs(v0).max())
    assert gap < 1e-10, (path, gap)
    line = f"NSGS on NumPy's condensation error {err:.1e}, |(r, v) - manufactured| = {gap:.1e}"
    if p > 0:
        line += f", |G^T v + b| = {np.abs(gm.T @ v + b).max():.1e} (gfc3d has no G)"
    elif d == 3:
        rg, vg = siconos_global_3d(m, h, f, w, mu)
        cross = max(np.abs(rg - r).max() / np.abs(r).max(), np.abs(vg - v).max() / np.abs(v).max())
        assert cross < 1e-10, (path, cross)
        line += f", gfc3d NSN_AC (global) differs by {cross:.1e}"
    return r, u, v, line


def store_solutions(exe, manufactured):
    for name in LOCAL:
        path = os.path.join(HERE, name)
        r, u, err = siconos_solve(path)
        r0, u0 = manufactured[name]
        gap = np.abs(r - r0).max() / np.abs(r0).max()
        assert gap < 1e-10, (name, gap)
        text = " ".join("%.17g" % v for v in np.concatenate([r, u]))
        subprocess.run([exe, "solution", path], input=text, text=True, check=True)
        merit = subprocess.check_output([exe, "merit", path], text=True).strip() if name == "fc3d_csc.hdf5" else "-"
        print(f"{name}: Siconos NSGS error {err:.1e}, |r - manufactured| / |r| = {gap:.1e}, FCLib merit {merit}")
    for name in GLOBAL:
        path = os.path.join(HERE, name)
        r, u, v, line = solve_global(path, manufactured[name])
        text = " ".join("%.17g" % x for x in np.concatenate([r, u, v]))
        subprocess.run([exe, "global-solution", path], input=text, text=True, check=True)
        print(f"{name}: {line}")


def copy_latest(src, dst):
    """The same groups and datasets in HDF5's newest format, arrays deflated."""
    with h5py.File(src, "r") as f, h5py.File(dst, "w", libver="latest") as g:
        def visit(name, obj):
            if isinstance(obj, h5py.Group):
                g.require_group(name)
            elif obj.shape and obj.shape[0] > 1:
                g.create_dataset(name, data=obj[()], chunks=True, compression="gzip")
            else:
                g.create_dataset(name, data=obj[()])
        f.visititems(visit)


def broken(src, dst, edit):
    shutil.copyfile(os.path.join(HERE, src), os.path.join(HERE, dst))
    with h5py.File(os.path.join(HERE, dst), "r+") as f:
        edit(f)


def replace(f, name, value, dtype=None):
    value = np.asarray(value, dtype=dtype if dtype else f[name].dtype)
    del f[name]
    f.create_dataset(name, data=value)


def set_entry(name, k, value):
    def edit(f):
        a = f[name][()]
        a[k] = value
        replace(f, name, a)
    return edit


BAD = [
    # (file, from, edit): each breaks one thing of a good file
    ("bad_spacedim.hdf5", "fc2d_triplet.hdf5", lambda f: replace(f, "fclib_local/spacedim", [4])),
    ("bad_rows.hdf5", "fc2d_triplet.hdf5", lambda f: replace(f, "fclib_local/spacedim", [3])),
    ("bad_mu_length.hdf5", "fc2d_triplet.hdf5", lambda f: replace(f, "fclib_local/vectors/mu", [0.5, 0.3, 0.4, 0.6])),
    ("bad_mu_negative.hdf5", "fc2d_triplet.hdf5", set_entry("fclib_local/vectors/mu", 2, -0.1)),
    ("bad_w_nan.hdf5", "fc3d_csc.hdf5", set_entry("fclib_local/W/x", 3, np.nan)),
    ("bad_q_inf.hdf5", "fc3d_csc.hdf5", set_entry("fclib_local/vectors/q", 1, np.inf)),
    ("bad_q_length.hdf5", "fc3d_csc.hdf5", lambda f: replace(f, "fclib_local/vectors/q", np.ones(9))),
    ("bad_no_q.hdf5", "fc3d_csc.hdf5", lambda f: f.__delitem__("fclib_local/vectors/q")),
    ("bad_row_index.hdf5", "fc2d_triplet.hdf5", set_entry("fclib_local/W/i", 5, 10)),
    ("bad_column_index.hdf5", "fc2d_triplet.hdf5", set_entry("fclib_local/W/p", 7, -1)),
    ("bad_csc_index.hdf5", "fc3d_csc.hdf5", set_entry("fclib_local/W/i", 4, 12)),
    ("bad_csc_pointers.hdf5", "fc3d_csc.hdf5", set_entry("fclib_local/W/p", 3, 40)),
    ("bad_csr_pointers.hdf5", "fc3d_csr.hdf5", set_entry("fclib_local/W/p", 12, 1000)),
    ("bad_short_x.hdf5", "fc2d_triplet.hdf5", lambda f: replace(f, "fclib_local/W/x", f["fclib_local/W/x"][:20])),
    ("bad_not_square.hdf5", "fc2d_triplet.hdf5", lambda f: replace(f, "fclib_local/W/n", [12])),
    ("bad_storage.hdf5", "fc3d_csc.hdf5", lambda f: replace(f, "fclib_local/W/nz", [-3])),
    ("bad_asymmetric.hdf5", "fc3d_csc.hdf5", set_entry("fclib_local/W/x", 1, 7.0)),
    # W declared 2·10⁹ × 2·10⁹ (its dense copy: 32 EB), its arrays small
    ("bad_huge.hdf5", "fc2d_triplet.hdf5", lambda f: [replace(f, "fclib_local/W/" + k, [2_000_000_000]) for k in "mn"]),
    # global problems
    ("bad_global_g_dependent.hdf5", "global3d_g.hdf5", lambda f: add_g(f, [1, 1])),
    ("bad_global_g_rows.hdf5", "global3d_g.hdf5", lambda f: replace(f, "fclib_global/G/m", [14])),
    ("bad_global_b_length.hdf5", "global3d_g.hdf5", lambda f: replace(f, "fclib_global/vectors/b", np.ones(3))),
    ("bad_global_no_b.hdf5", "global3d_g.hdf5", lambda f: f.__delitem__("fclib_global/vectors/b")),
    ("bad_global_indefinite.hdf5", "global2d.hdf5", set_entry("fclib_global/M/x", 0, -5.0)),
    ("bad_global_asymmetric.hdf5", "global2d.hdf5", set_entry("fclib_global/M/x", 1, 7.0)),
    ("bad_global_h_rows.hdf5", "global3d.hdf5", lambda f: replace(f, "fclib_global/H/m", [12])),
    ("bad_global_h_index.hdf5", "global3d.hdf5", set_entry("fclib_global/H/i", 3, 99)),
    ("bad_global_m_index.hdf5", "global3d.hdf5", set_entry("fclib_global/M/p", 4, 15)),
    ("bad_global_f_length.hdf5", "global3d.hdf5", lambda f: replace(f, "fclib_global/vectors/f", np.ones(14))),
    ("bad_global_w_nan.hdf5", "global3d.hdf5", set_entry("fclib_global/vectors/w", 2, np.nan)),
    ("bad_global_no_h.hdf5", "global2d.hdf5", lambda f: f.__delitem__("fclib_global/H")),
    ("bad_global_spacedim.hdf5", "global2d.hdf5", lambda f: replace(f, "fclib_global/spacedim", [4])),
    # M and H declared 2·10⁹ rows, f of 15 entries
    ("bad_global_huge.hdf5", "global3d.hdf5",
     lambda f: [replace(f, "fclib_global/" + k, [2_000_000_000]) for k in ["M/m", "M/n", "H/m"]]),
]


def add_g(f, rows):
    """G replaced by columns e_rows[k] (compressed columns, as fclib_write_global
    stores a matrix): equal rows make its columns linearly dependent."""
    del f["fclib_global/G"]
    g = f.create_group("fclib_global/G")
    k = len(rows)
    for name, v in [("m", [15]), ("n", [k]), ("nz", [-1]), ("nzmax", [k])]:
        g.create_dataset(name, data=np.array(v, dtype=np.int32))
    g.create_dataset("p", data=np.arange(k + 1, dtype=np.int32))
    g.create_dataset("i", data=np.array(rows, dtype=np.int32))
    g.create_dataset("x", data=np.ones(k))


def main():
    with tempfile.TemporaryDirectory() as tmp:
        exe = build(tmp)
        out = subprocess.check_output([exe, "problems", HERE], text=True)
        manufactured = {}
        for line in out.splitlines():
            name, rest = line.split(" r ")
            r, rest = rest.split(" u ")
            vectors = [r] + rest.split(" v ")
            manufactured[name] = tuple(np.array(x.split(), float) for x in vectors)
        store_solutions(exe, manufactured)
    copy_latest(os.path.join(HERE, "fc3d_csc.hdf5"), os.path.join(HERE, "fc3d_csc_latest.hdf5"))
    for dst, src, edit in BAD:
        broken(src, dst, edit)
    print(f"wrote {len(LOCAL)} local and {len(GLOBAL)} global problems with Siconos' solutions, a mixed problem, "
          f"fc3d_csc_latest.hdf5 and {len(BAD)} broken files in {HERE}")


if __name__ == "__main__":
    sys.exit(main())
