#!/usr/bin/python3
"""Writes the FCLib test files of tests/fclib.rs into this directory.

1. Builds make_fclib.c (the FCLib C library, Debian's libfclib-dev) and runs
   it: the problems are written by fclib_write_local / fclib_write_global.
2. Reads each local problem back with h5py (a reader independent of both
   FCLib and signorini), solves it with Siconos (Debian's python3-siconos:
   fc2d / fc3d NSGS to 1e-14), checks Siconos' forces against the problem's
   manufactured solution, and stores Siconos' r and u as the file's
   /solution through fclib_write_solution.
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


def siconos_solve(path):
    with h5py.File(path, "r") as f:
        loc = f["fclib_local"]
        d = int(loc["spacedim"][0])
        w, q, mu = dense(loc["W"]), loc["vectors/q"][()], loc["vectors/mu"][()]
    n = len(q)
    prefix = "SICONOS_FRICTION_2D_" if d == 2 else "SICONOS_FRICTION_3D_"
    so = sn.SolverOptions(getattr(sn, prefix + "NSGS"))
    so.dparam[sn.SICONOS_DPARAM_TOL] = 1e-14
    so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 100000
    r, u = np.zeros(n), np.zeros(n)
    driver = sn.fc2d_driver if d == 2 else sn.fc3d_driver
    info = driver(sn.FrictionContactProblem(d, n // d, w, q, mu), r, u, so)
    err = so.dparam[sn.SICONOS_DPARAM_RESIDU]
    assert info == 0 and err < 1e-13, (path, info, err)
    return r, u, err


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
]


def main():
    with tempfile.TemporaryDirectory() as tmp:
        exe = build(tmp)
        out = subprocess.check_output([exe, "problems", HERE], text=True)
        manufactured = {}
        for line in out.splitlines():
            name, rest = line.split(" r ")
            r, u = rest.split(" u ")
            manufactured[name] = (np.array(r.split(), float), np.array(u.split(), float))
        store_solutions(exe, manufactured)
    copy_latest(os.path.join(HERE, "fc3d_csc.hdf5"), os.path.join(HERE, "fc3d_csc_latest.hdf5"))
    for dst, src, edit in BAD:
        broken(src, dst, edit)
    print(f"wrote {len(LOCAL)} local problems with Siconos' solutions, a global and a mixed problem, "
          f"fc3d_csc_latest.hdf5 and {len(BAD)} broken files in {HERE}")


if __name__ == "__main__":
    sys.exit(main())
