#!/usr/bin/python3
"""Writes the FCLib problems of multibody codes' kind (LMGC90, Siconos) that
tests/integration/fclib.rs reads as they are written, with h5py (no FCLib C
library needed):

- rigid_boxes.hdf5: columns of rigid boxes on the ground, four corner contacts
  per face, W = H^T M^-1 H of 3 rows per contact and 6 DOFs per box: rank
  6 x boxes, far below its rows (the normal forces are not unique); q the free
  velocity of gravity and a sideways push on the top boxes, one time step.
- rigid_spheres.hdf5: a cubic pile of rigid spheres on the ground (rank
  deficient too), pushed sideways, W stored upper triangle only (a symmetric
  matrix stored as one triangle), compressed by rows.
- rigid_spheres_asymmetric.hdf5: the same pile with W made nonsymmetric by
  1e-3 of max |W| on its pattern (as an LMGC90 export whose W came from an
  unsymmetric assembly), stored in full.
- fe_block_upper.hdf5: a global problem (an elastic lattice block on the
  ground, M = mass + h^2 K), M stored as its upper triangle (as LMGC90 writes
  its FE global problems), H and f full.
- zero_solution.hdf5: rigid_boxes with a /solution/r of zeros (a writer that
  stored its initial guess): not a solution of the problem.

Usage: /usr/bin/python3 tests/data/fclib/make_rigid.py
Needs python3-h5py and numpy; reruns write the same numbers.
"""
import os

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
H_STEP = 0.01
GRAVITY = 9.81


def frame(n):
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return [n, t1, np.cross(n, t1)]


def contact_columns(ndof, upper, lower, point, n, centres):
    """The 3 columns of H of a contact at `point`, normal n from lower to upper."""
    cols = []
    for e in frame(np.asarray(n, float)):
        c = np.zeros(ndof)
        for body, sign in ((upper, 1.0), (lower, -1.0)):
            if body is None:
                continue
            arm = point - centres[body]
            c[6 * body:6 * body + 3] += sign * e
            c[6 * body + 3:6 * body + 6] += sign * np.cross(arm, e)
        cols.append(c)
    return cols


def rigid_problem(centres, masses, inertias, contacts, push):
    """W = H^T M^-1 H, q = H^T (h M^-1 f) for bodies at rest, f gravity + push."""
    nb = len(centres)
    ndof = 6 * nb
    h = np.column_stack([c for (u, l, p, n) in contacts
                         for c in contact_columns(ndof, u, l, np.asarray(p, float), n, centres)])
    minv = np.zeros(ndof)
    f = np.zeros(ndof)
    for b in range(nb):
        minv[6 * b:6 * b + 3] = 1.0 / masses[b]
        minv[6 * b + 3:6 * b + 6] = 1.0 / np.asarray(inertias[b])
        f[6 * b + 2] = -masses[b] * GRAVITY
        f[6 * b:6 * b + 3] += push[b]
    w = h.T @ (minv[:, None] * h)
    q = h.T @ (H_STEP * minv * f)
    return w, q


def boxes(nx=2, ny=2, nz=4):
    a, b, c = 0.5, 0.4, 0.25  # half sizes
    centres, contacts, push = [], [], []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                centres.append(np.array([3.0 * a * i, 3.0 * b * j, c * (2 * k + 1)]))
                body = len(centres) - 1
                below = None if k == 0 else body - 1
                for sx in (-1, 1):
                    for sy in (-1, 1):
                        p = centres[body] + [sx * a, sy * b, -c]
                        contacts.append((body, below, p, [0.0, 0.0, 1.0]))
                push.append([0.2 * (k + 1) / nz, 0.1 * np.sin(i + 2 * j), 0.0])
    mass = 8 * a * b * c * 1000.0 / 100.0
    inertia = [mass / 3 * (b * b + c * c), mass / 3 * (a * a + c * c), mass / 3 * (a * a + b * b)]
    n = len(centres)
    w, q = rigid_problem(centres, [mass] * n, [inertia] * n, contacts, np.array(push) * mass)
    return w, q, np.full(len(contacts), 0.5)


def spheres(k=4, layers=3):
    rad = 0.5
    centres, contacts = [], []
    index = {}
    for z in range(layers):
        for y in range(k):
            for x in range(k):
                index[(x, y, z)] = len(centres)
                centres.append(np.array([x, y, rad + z], float))
    for (x, y, z), i in index.items():
        if z == 0:
            contacts.append((i, None, centres[i] - [0, 0, rad], [0.0, 0.0, 1.0]))
        for d in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
            j = index.get((x + d[0], y + d[1], z + d[2]))
            if j is not None:
                n = centres[j] - centres[i]
                contacts.append((j, i, centres[i] + rad * n, n))
    nb = len(centres)
    mass, inertia = 1.0, 0.4 * rad * rad
    push = np.array([[0.3 * np.sin(1.7 * i), 0.2 * np.cos(0.9 * i), 0.0] for i in range(nb)])
    w, q = rigid_problem(centres, [mass] * nb, [[inertia] * 3] * nb, contacts, push)
    return w, q, np.full(len(contacts), 0.3)


def sparse_group(g, name, a, storage, triangle=None):
    """An FCLib sparse matrix group: storage 'csc' (nz = -1), 'csr' (nz = -2)
    or 'triplet'; with triangle 'upper' only the entries on and above the diagonal."""
    a = np.array(a)
    if triangle == "upper":
        a = np.triu(a)
    a[np.abs(a) < 1e-14 * np.abs(a).max()] = 0.0
    m, n = a.shape
    grp = g.create_group(name)
    mat = a if storage != "csr" else a.T
    cols = [np.nonzero(mat[:, j])[0] for j in range(mat.shape[1])]
    p = np.concatenate([[0], np.cumsum([len(c) for c in cols])]).astype(np.int32)
    i = np.concatenate(cols).astype(np.int32)
    x = np.concatenate([mat[c, j] for j, c in enumerate(cols)])
    nz = {"csc": -1, "csr": -2}.get(storage, len(x))
    if storage == "triplet":
        rows, colidx = np.nonzero(a)
        i, p, x = rows.astype(np.int32), colidx.astype(np.int32), a[rows, colidx]
    for key, v in (("m", m), ("n", n), ("nz", nz), ("nzmax", len(x))):
        grp.create_dataset(key, data=np.array([v], np.int32))
    opts = dict(compression="gzip", shuffle=True) if len(x) > 1000 else {}
    grp.create_dataset("p", data=p, **opts)
    grp.create_dataset("i", data=i, **opts)
    grp.create_dataset("x", data=x, **opts)


def write_local(name, w, q, mu, storage="csc", triangle=None, solution=None):
    with h5py.File(os.path.join(HERE, name), "w") as f:
        loc = f.create_group("fclib_local")
        loc.create_dataset("spacedim", data=np.array([3], np.int32))
        sparse_group(loc, "W", w, storage, triangle)
        vec = loc.create_group("vectors")
        vec.create_dataset("q", data=q)
        vec.create_dataset("mu", data=mu)
        info = f.create_group("fclib_local/info")
        info.create_dataset("title", data=np.bytes_(name))
        if solution is not None:
            s = f.create_group("solution")
            s.create_dataset("r", data=solution[0])
            s.create_dataset("u", data=solution[1])


def fe_block(nx=3, ny=3, nz=3):
    """A lattice of masses and springs (nearest and diagonal neighbours) on the
    ground: M_global = mass + h^2 K (SPD), H the bottom nodes' contacts."""
    nodes = [(x, y, z) for z in range(nz) for y in range(ny) for x in range(nx)]
    idx = {p: i for i, p in enumerate(nodes)}
    n = 3 * len(nodes)
    k = np.zeros((n, n))
    for p, i in idx.items():
        for d in ((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 0, 1), (0, 1, 1), (1, -1, 0), (1, 0, -1), (0, 1, -1)):
            q = (p[0] + d[0], p[1] + d[1], p[2] + d[2])
            j = idx.get(q)
            if j is None:
                continue
            e = np.asarray(d, float) / np.linalg.norm(d)
            ke = 1e4 * np.outer(e, e)
            for a, b, s in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
                k[3 * a:3 * a + 3, 3 * b:3 * b + 3] += s * ke
    mass = np.full(n, 1.0)
    m = np.diag(mass) + H_STEP ** 2 * k
    bottom = [i for p, i in idx.items() if p[2] == 0]
    h = np.zeros((n, 3 * len(bottom)))
    for c, i in enumerate(bottom):
        for r, e in enumerate(frame(np.array([0.0, 0.0, 1.0]))):
            h[3 * i:3 * i + 3, 3 * c + r] = e
    f = np.zeros(n)
    f[2::3] = -H_STEP * GRAVITY * mass[2::3]
    f[0::3] = 0.02 * np.sin(np.arange(len(nodes)))
    w = np.zeros(h.shape[1])
    return m, h, f, w, np.full(len(bottom), 0.4)


def write_global(name, m, h, f, w, mu):
    with h5py.File(os.path.join(HERE, name), "w") as g:
        gl = g.create_group("fclib_global")
        gl.create_dataset("spacedim", data=np.array([3], np.int32))
        sparse_group(gl, "M", m, "csc", "upper")
        sparse_group(gl, "H", h, "csc")
        vec = gl.create_group("vectors")
        for key, v in (("f", f), ("w", w), ("mu", mu)):
            vec.create_dataset(key, data=v)


def main():
    w, q, mu = boxes()
    write_local("rigid_boxes.hdf5", w, q, mu)
    print(f"rigid_boxes: {len(q)} rows, rank {np.linalg.matrix_rank(w)}")
    write_local("zero_solution.hdf5", w, q, mu, solution=(np.zeros(len(q)), q))
    w, q, mu = spheres()
    write_local("rigid_spheres.hdf5", w, q, mu, storage="csr", triangle="upper")
    print(f"rigid_spheres: {len(q)} rows, rank {np.linalg.matrix_rank(w)}")
    rng = np.random.default_rng(7)
    pattern = np.abs(w) > 1e-14 * np.abs(w).max()
    wa = w + 1e-3 * np.abs(w).max() * rng.uniform(-1, 1, w.shape) * pattern
    write_local("rigid_spheres_asymmetric.hdf5", wa, q, mu)
    asym = np.abs(wa - wa.T).max() / np.abs(wa).max()
    print(f"rigid_spheres_asymmetric: max |W - W^T| / max |W| = {asym:.1e}")
    m, h, f, wv, mu = fe_block()
    write_global("fe_block_upper.hdf5", m, h, f, wv, mu)
    print(f"fe_block_upper: n = {m.shape[0]}, {h.shape[1] // 3} contacts")


if __name__ == "__main__":
    main()
