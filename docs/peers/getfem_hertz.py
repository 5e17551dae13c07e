"""Hertz sphere in GetFEM: a quarter of the elastic hemisphere (R = 1, E = 1, nu = 0.3,
centre (0, 0, 1), pole at the origin) in P2 tetrahedra pressed by 0.01 on the rigid plane
z = 0; nodal contact with the rigid obstacle (Alart-Curnier augmented Lagrangian,
generalized Newton). Symmetry planes x = 0 and y = 0 (normal displacement zero), the
flat face z = 1 moved by (0, 0, -0.01). Prints the load of the whole sphere, p0 (the
contact stress -sigma_zz at the pole), a (from the moment of the nodal contact forces,
a = sqrt(5/2 sum F r^2 / sum F), as signorini's report computes it) and their errors
against Hertz's formulas at that load (docs/theory/validation-cases.md §2), and the
seconds from the start to the end of the solve. The peer of the signorini scene
examples/hertz3d_quadratic.toml, for docs/performance/quadratic.md:

    gmsh -3 -setnumber level 1 getfem_hertz_quarter.geo -o getfem_hertz_level1.msh
    /usr/bin/python3 getfem_hertz.py getfem_hertz_level1.msh [-v]
"""
import sys
import time

import numpy as np
import getfem as gf

t0 = time.perf_counter()
E, NU, R, DELTA = 1.0, 0.3, 1.0, 0.01
SYM_X, SYM_Y, TOP, DOME = 11, 12, 13, 14

mesh = gf.Mesh('import', 'gmsh', sys.argv[1])
mfu = gf.MeshFem(mesh, 3)
mfu.set_classical_fem(2)
mim = gf.MeshIm(mesh, gf.Integ('IM_TETRAHEDRON(5)'))

md = gf.Model('real')
md.add_fem_variable('u', mfu)
lam = E * NU / ((1 + NU) * (1 - 2 * NU))
mu = E / (2 * (1 + NU))
md.add_initialized_data('lambda', [lam])
md.add_initialized_data('mu', [mu])
md.add_isotropic_linearized_elasticity_brick(mim, 'u', 'lambda', 'mu')

mfr = gf.MeshFem(mesh, 1)
mfr.set_classical_fem(1)
md.add_initialized_data('top', [0.0, 0.0, -DELTA])
md.add_normal_Dirichlet_condition_with_multipliers(mim, 'u', 2, SYM_X)
md.add_normal_Dirichlet_condition_with_multipliers(mim, 'u', 2, SYM_Y)
md.add_Dirichlet_condition_with_simplification('u', TOP, 'top')

ncontact = mfu.basic_dof_on_region(DOME).size // 3
md.add_variable('lambda_n', ncontact)
md.add_initialized_data('r', [E])
md.add_nodal_contact_with_rigid_obstacle_brick(mim, 'u', 'lambda_n', 'r', DOME, 'z')

opts = ['max_res', 1e-9 * E * DELTA, 'max_iter', 100] + (['noisy'] if '-v' in sys.argv else [])
md.solve(*opts)
t_solve = time.perf_counter() - t0

# Contact forces: lambda_n is the equivalent nodal force of each dome node.
lam_n = -md.variable('lambda_n')
dofs = mfu.basic_dof_on_region(DOME)[::3]
pts = mfu.basic_dof_nodes(dofs)
force = np.maximum(lam_n, 0.0)
# Quarter model: the whole sphere's load is 4 times the quarter's.
p_total = 4.0 * force.sum()
r2 = pts[0] ** 2 + pts[1] ** 2
a_mom = np.sqrt(2.5 * (force * r2).sum() / force.sum())
# p0: -sigma_zz at the pole, interpolated on P1 nodes.
sig = md.interpolation('-(lambda*Trace(Grad_u)*Id(3) + mu*(Grad_u+Grad_u\'))(3,3)', mfr)
pole = mfr.basic_dof_nodes()
ip = np.argmin(np.sum(pole ** 2, axis=0))
p0 = float(sig[ip])
es = E / (1 - NU ** 2)
a_h = (3 * p_total * R / (4 * es)) ** (1 / 3)
p0_h = 3 * p_total / (2 * np.pi * a_h ** 2)
print(f"dofs {mfu.nbdof()} contact_nodes {ncontact} load {p_total:.6e}")
print(f"p0 {p0:.6e} hertz {p0_h:.6e} error {abs(p0 - p0_h) / p0_h:.4%}")
print(f"a {a_mom:.6e} hertz {a_h:.6e} error {abs(a_mom - a_h) / a_h:.4%}")
print(f"solve_s {t_solve:.3f}")
