"""Moves the nodes of a straight block of parabolic.geo (a Gmsh 4.1 ASCII
file) onto the parabolic cut z = 0.5 + C x^2 (see parabolic.geo):
    python3 parabolic.py straight.msh out.msh lower|upper
Only the coordinates of the $Nodes section change."""
import sys

C = 0.25


def moved(x, z, side):
    if side == "lower":
        return z + C * x * x * z / 0.5
    return z + C * x * x * (1.0 - z) / 0.5


def main(src, dst, side):
    lines = open(src).read().split("\n")
    i = lines.index("$Nodes") + 1
    blocks = int(lines[i].split()[0])
    i += 1
    for _ in range(blocks):
        count = int(lines[i].split()[3])
        i += 1 + count  # the block header, then the node tags
        for k in range(i, i + count):
            x, y, z = (float(v) for v in lines[k].split()[:3])
            lines[k] = f"{x!r} {y!r} {moved(x, z, side)!r}"
        i += count
    open(dst, "w").write("\n".join(lines))


if __name__ == "__main__":
    main(*sys.argv[1:4])
