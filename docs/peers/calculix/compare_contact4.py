"""Compares signorini's displacements of contact4.toml with CalculiX's of contact4.inp.

    ccx contact4            # writes contact4.dat (*NODE PRINT U at the last increment)
    signorini run contact4.toml --out out
    /usr/bin/python3 compare_contact4.py contact4.inp contact4.dat out/displacement.csv

Matches the nodes by their coordinates and prints, per node, both displacements
and the largest difference relative to the largest displacement.
"""
import csv
import sys


def ccx_nodes(inp):
    nodes, on = {}, False
    for line in open(inp):
        s = line.strip()
        if s.startswith('*'):
            on = s.upper().startswith('*NODE') and not s.upper().startswith('*NODE PRINT')
            continue
        if on and s:
            f = s.split(',')
            nodes[int(f[0])] = tuple(round(float(x), 9) for x in f[1:4])
    return nodes


def ccx_displacements(dat):
    """The last `displacements` block of a ccx .dat file: node -> (ux, uy, uz)."""
    blocks, cur = [], None
    for line in open(dat):
        if line.strip().startswith('displacements'):
            cur = {}
            blocks.append(cur)
            continue
        f = line.split()
        if cur is not None and len(f) == 4 and f[0].isdigit():
            cur[int(f[0])] = tuple(float(x) for x in f[1:])
        elif cur is not None and f and not f[0].isdigit():
            cur = None
    return blocks[-1]


def signorini_displacements(path):
    out = {}
    for row in csv.DictReader(open(path)):
        key = tuple(round(float(row[k]), 9) for k in ('x', 'y', 'z'))
        out.setdefault(key, []).append(tuple(float(row[k]) for k in ('ux', 'uy', 'uz')))
    return out


def main(inp, dat, csv_path):
    coords = ccx_nodes(inp)
    ccx = ccx_displacements(dat)
    sig = signorini_displacements(csv_path)
    scale = max(abs(c) for u in ccx.values() for c in u)
    worst = (-1.0, 0)
    for node, u in sorted(ccx.items()):
        # coincident nodes of the two bodies (none in contact4): the nearest answer
        v = min(sig[coords[node]], key=lambda w: sum((a - b) ** 2 for a, b in zip(u, w)))
        d = max(abs(a - b) for a, b in zip(u, v))
        worst = max(worst, (d, node))
        print(f'{node:4d} ccx ' + ' '.join(f'{c: .6e}' for c in u)
              + '  signorini ' + ' '.join(f'{c: .6e}' for c in v) + f'  diff {d / scale:.2e}')
    print(f'largest difference {worst[0]:.3e} at node {worst[1]} '
          f'({worst[0] / scale:.2e} of the largest displacement {scale:.3e})')


if __name__ == '__main__':
    main(*sys.argv[1:4])
