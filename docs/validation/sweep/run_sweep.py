#!/usr/bin/env python3
"""Runs every sweep scene (s*.toml beside this file) with a time bound and
prints, per scene and path, the exit code, wall and CPU seconds, the first
error line, and the balance of forces at the last step: the applied forces
(from the scene's `force` entries at their last scale, 1 here) plus the
supports' reactions plus each rigid master's force on the body (the
contacts' `force` whose master is rigid) must add to zero.

  python3 run_sweep.py BIN [OUTDIR] [--mpi]
"""
import json, os, subprocess, sys, time, tomllib, resource

here = os.path.dirname(os.path.abspath(__file__))
binary = os.path.abspath(sys.argv[1])
outroot = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else "/tmp/sweep_out"
mpi = "--mpi" in sys.argv


def balance(scene, report):
    dim = scene["dimension"]
    rigid = {b["name"] for b in scene.get("bodies", []) if "rigid" in b}
    total = [0.0] * dim
    scale = max((abs(x) for b in scene.get("boundary", []) for x in b.get("force", [])), default=0.0)
    for b in scene.get("boundary", []):
        for i, x in enumerate(b.get("force", [])):
            total[i] += x
    step = report["steps"][-1]
    for r in step.get("reactions", []):
        for i, x in enumerate(r["force"]):
            total[i] += x
        scale = max(scale, max(abs(x) for x in r["force"]))
    contacts = {c["name"]: c for c in scene.get("contact", [])}
    for c in step.get("contacts", []):
        if contacts[c["name"]]["master"]["body"] in rigid:
            for i, x in enumerate(c["force"]):
                total[i] += x
    if model_axi(scene):
        total[0] = 0.0
    return max(abs(x) for x in total) / max(scale, 1e-300)


reference = {}


def contact_forces(report):
    """Every contact's force vector at every step, in order."""
    return [x for st in report["steps"] for c in st.get("contacts", []) for x in c["force"]]


def difference(a, b):
    """max |a - b| / max |a|: the relative difference of two runs' contact forces."""
    if len(a) != len(b):
        return float("inf")
    scale = max((abs(x) for x in a), default=0.0)
    return max((abs(x - y) for x, y in zip(a, b)), default=0.0) / max(scale, 1e-300)


def model_axi(scene):
    return scene.get("model") == "axisymmetric"


def run(name, path, ranks):
    out = os.path.join(outroot, f"{name}_{path}_{ranks}")
    cmd = [binary, "run", os.path.join(here, name + ".toml"), "--out", out, "--path", path]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        code, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        code, err = "timeout", ""
    wall = time.time() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    lines = [l for l in err.splitlines() if l.strip() and not l.startswith(("warning", "note"))]
    first = next((l for l in lines if "rror" in l or "not converged" in l.lower()), lines[0] if lines else "")
    check = ""
    rep = os.path.join(out, "report.json")
    if code in (0, 2) and os.path.exists(rep):
        with open(os.path.join(here, name + ".toml"), "rb") as f:
            scene = tomllib.load(f)
        with open(rep) as f:
            report = json.load(f)
        forces = contact_forces(report)
        traction = any("traction" in b for b in scene.get("boundary", []))
        held = "n/a (traction)" if traction else f"{balance(scene, report):.1e}"
        check = f"balance {held}; N {report['steps'][-1].get('normal_force', 0):.6g}"
        if (name, "condensed", 1) in reference and (path, ranks) != ("condensed", 1):
            check += f"; vs condensed 1 rank {difference(reference[(name, 'condensed', 1)], forces):.1e}"
        reference[(name, path, ranks)] = forces
    written = os.path.exists(out)
    print(f"| {name} | {path} | {ranks} | {code} | {wall:.1f} | {cpu:.1f} | {check} | {'written' if written else 'nothing written'} | {first[:300]} |", flush=True)


# The meshes of the .geo files are made here (gmsh on PATH) when missing:
# the repository keeps the .geo files and the hand-written .msh files only.
for geo in sorted(f for f in os.listdir(here) if f.endswith(".geo")):
    msh = os.path.join(here, geo[:-4] + ".msh")
    if not os.path.exists(msh):
        dim = "-3" if "Box(" in open(os.path.join(here, geo)).read() else "-2"
        subprocess.run(["gmsh", dim, os.path.join(here, geo), "-o", msh], capture_output=True, check=True)

names = sorted(f[:-5] for f in os.listdir(here) if f.startswith("s") and f.endswith(".toml"))
only = os.environ.get("ONLY")
for name in names:
    if only and only not in name:
        continue
    for path in ("condensed", "direct"):
        run(name, path, 1)
    if mpi:
        run(name, "condensed", 2)
