import sys
n, nx, nz, sub = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
h = float(sys.argv[6]) if len(sys.argv) > 6 else 0.25
out = []
out.append(f'''# A stack of {n} steel blocks (1 x 1 x {h} m, hex8, {nx} x {nx} x {nz} cells each)
# on a rigid floor, the top face of the top block pressed down by 0.1 mm:
# a 3D multi-body assembly for the per-rank memory and time figures of the
# docs/performance/subdomains.md ("Ranks: memory and time per rank"). Every block rests on the one
# below (node_to_face, matching meshes), pinned in x and y at two corners;
# the blocks between the top and the floor are held in z by contact alone.
#
#   mpirun -n 2 target/release/signorini run {sys.argv[5]}
title = "Stack of {n} blocks on a rigid floor (3D)"
dimension = 3
model = "solid"

[[materials]]
name = "steel"
young = 210e9
poisson = 0.3
''')
for i in range(n):
    z0 = h * i
    out.append(f'''[[bodies]]
name = "b{i}"
material = "steel"
subdomains = {sub}
mesh = {{ generator = "box", origin = [0.0, 0.0, {z0}], size = [1.0, 1.0, {h}], divisions = [{nx}, {nx}, {nz}] }}

[[boundary]]
name = "pin{i}"
body = "b{i}"
point = [0.0, 0.0, {z0}]
displacement = {{ x = 0.0, y = 0.0 }}

[[boundary]]
name = "roll{i}"
body = "b{i}"
point = [1.0, 0.0, {z0}]
displacement = {{ y = 0.0 }}
''')
out.append(f'''[[bodies]]
name = "floor"
rigid = {{ shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}

[[boundary]]
name = "press"
body = "b{n-1}"
surface = "zmax"
displacement = {{ z = -1e-4 }}

[[contact]]
name = "b0-floor"
slave = {{ body = "b0", surface = "zmin" }}
master = {{ body = "floor" }}
''')
for i in range(1, n):
    out.append(f'''[[contact]]
name = "b{i}-b{i-1}"
slave = {{ body = "b{i}", surface = "zmin" }}
master = {{ body = "b{i-1}", surface = "zmax" }}
discretization = "node_to_face"
''')
out.append('''[solver]
method = "status"
path = "condensed"
''')
print("\n".join(out))
