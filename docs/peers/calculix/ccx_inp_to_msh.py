"""Converts a CalculiX (Abaqus-format) input deck of C3D20/C3D20R/C3D8 solids into a
Gmsh 2.2 mesh that a signorini scene reads:

- each connected set of elements (elements sharing nodes) becomes a physical volume
  `part1`, `part2`, ... in the order of their first element;
- each element-face `*SURFACE` becomes a physical surface of its name (Quad8 or Quad4
  faces), each `*DLOAD ..., Pn` face set a physical surface `dload1`, `dload2`, ...;
- each `*NSET` becomes a physical group of points of its name.

Only what a translation needs is read: `*NODE`, `*ELEMENT`, `*NSET` (lists, and
`GENERATE`), `*SURFACE` (element, Sn lines), `*DLOAD` (element, Pn, value). The
material, steps and contact definitions are translated by hand into the scene.

    /usr/bin/python3 ccx_inp_to_msh.py contact4.inp contact4.msh
"""
import sys
from collections import defaultdict

# C3D20 mid-side nodes (0-based): the corner pair of nodes 8..19 in the Abaqus order.
ABAQUS_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
                (0, 4), (1, 5), (2, 6), (3, 7)]
# Gmsh's 20-node hexahedron (type 17): the corner pair of nodes 8..19.
GMSH_EDGES = [(0, 1), (0, 3), (0, 4), (1, 2), (1, 5), (2, 3), (2, 6), (3, 7),
              (4, 5), (4, 7), (5, 6), (6, 7)]
# Abaqus faces S1..S6 of a hexahedron, corners in order (outward normal).
FACES = [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]


def cards(path):
    """Yields (keyword line, data lines) of the deck, comments dropped."""
    key, data = None, []
    for raw in open(path):
        line = raw.strip()
        if not line or line.startswith('**'):
            continue
        if line.startswith('*'):
            if key is not None:
                yield key, data
            key, data = line, []
        else:
            data.append(line)
    if key is not None:
        yield key, data


def option(key, name):
    for part in key.split(',')[1:]:
        k, _, v = part.partition('=')
        if k.strip().upper() == name:
            return v.strip()
    return None


def numbers(lines):
    return [x.strip() for line in lines for x in line.split(',') if x.strip()]


def read(path):
    nodes, elements, nsets, surfaces, dloads = {}, {}, {}, {}, []
    for key, data in cards(path):
        word = key.split(',')[0].upper()
        if word == '*NODE':
            for line in data:
                f = line.split(',')
                nodes[int(f[0])] = [float(x) for x in f[1:4]]
        elif word == '*ELEMENT':
            kind = option(key, 'TYPE').upper()
            if kind not in ('C3D20', 'C3D20R', 'C3D8', 'C3D8R'):
                sys.exit(f'element type {kind} is not converted (C3D20, C3D20R, C3D8)')
            count = 20 if kind.startswith('C3D20') else 8
            flat = [int(x) for x in numbers(data)]
            for i in range(0, len(flat), count + 1):
                elements[flat[i]] = flat[i + 1:i + count + 1]
        elif word == '*NSET':
            items = numbers(data)
            if 'GENERATE' in key.upper():
                a, b, s = (int(x) for x in (items + ['1'])[:3])
                items = [str(x) for x in range(a, b + 1, s)]
            nsets.setdefault(option(key, 'NSET'), []).extend(int(x) for x in items)
        elif word == '*SURFACE':
            faces = [(int(f[0]), int(f[1].strip().upper()[1:]))
                     for f in (line.split(',') for line in data)]
            surfaces[option(key, 'NAME')] = faces
        elif word == '*DLOAD':
            faces = [(int(f[0]), int(f[1].strip().upper()[1:]))
                     for f in (line.split(',') for line in data)]
            dloads.append(faces)
    return nodes, elements, nsets, surfaces, dloads


def face_nodes(conn, face):
    """The Quad8 (or Quad4) nodes of face `face` (1..6) of an Abaqus hexahedron."""
    corners = FACES[face - 1]
    quad = [conn[c] for c in corners]
    if len(conn) == 20:
        mid = {frozenset(e): conn[8 + i] for i, e in enumerate(ABAQUS_EDGES)}
        quad += [mid[frozenset((corners[i], corners[(i + 1) % 4]))] for i in range(4)]
    return quad


def to_gmsh(conn):
    if len(conn) == 8:
        return conn
    mid = {frozenset(e): conn[8 + i] for i, e in enumerate(ABAQUS_EDGES)}
    return conn[:8] + [mid[frozenset(e)] for e in GMSH_EDGES]


def parts(elements):
    """Connected sets of elements (sharing a node), in the order of their first element."""
    parent = {e: e for e in elements}

    def root(e):
        while parent[e] != e:
            parent[e] = parent[parent[e]]
            e = parent[e]
        return e

    by_node = defaultdict(list)
    for e, conn in elements.items():
        for n in conn:
            by_node[n].append(e)
    for es in by_node.values():
        for e in es[1:]:
            parent[root(e)] = root(es[0])
    groups = defaultdict(list)
    for e in sorted(elements):
        groups[root(e)].append(e)
    return sorted(groups.values(), key=lambda g: g[0])


def main(src, dst):
    nodes, elements, nsets, surfaces, dloads = read(src)
    names, rows = [], []
    for i, group in enumerate(parts(elements)):
        tag = len(names) + 1
        names.append((3, tag, f'part{i + 1}'))
        for e in group:
            conn = elements[e]
            rows.append((17 if len(conn) == 20 else 5, tag, to_gmsh(conn)))
    faces = list(surfaces.items()) + [(f'dload{i + 1}', f) for i, f in enumerate(dloads)]
    for name, face_list in faces:
        tag = len(names) + 1
        names.append((2, tag, name))
        for e, face in face_list:
            quad = face_nodes(elements[e], face)
            rows.append((16 if len(quad) == 8 else 3, tag, quad))
    for name, ids in nsets.items():
        tag = len(names) + 1
        names.append((0, tag, name))
        rows.extend((15, tag, [n]) for n in ids)
    with open(dst, 'w') as out:
        out.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n')
        out.write(f'{len(names)}\n')
        out.writelines(f'{d} {t} "{n}"\n' for d, t, n in names)
        out.write(f'$EndPhysicalNames\n$Nodes\n{len(nodes)}\n')
        out.writelines(f'{n} {x[0]!r} {x[1]!r} {x[2]!r}\n' for n, x in sorted(nodes.items()))
        out.write(f'$EndNodes\n$Elements\n{len(rows)}\n')
        for i, (kind, tag, conn) in enumerate(rows):
            out.write(f'{i + 1} {kind} 2 {tag} {tag} ' + ' '.join(map(str, conn)) + '\n')
        out.write('$EndElements\n')


if __name__ == '__main__':
    main(sys.argv[1], sys.argv[2])
