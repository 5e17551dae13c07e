#!/usr/bin/env bash
# The cluster command of docs/tutorial/04-mpi-and-large-models.md on this machine: `mpirun -n 2` on the stack
# example, one subdomain per rank, checked against the in-process run by
# tests/mpi.rs (which cargo test runs with --features mpi); here from the CLI.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out=target/ci-mpi
rm -rf "$out"
mpirun -n 2 --bind-to none target/release/signorini run examples/stack.toml --out "$out/stack"
python3 - "$out/stack/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["ranks"] == 2 and r["transport"] == "mpi" and r["converged"], r
print(f"mpirun -n 2 stack: {r['subdomains']} subdomains on {r['ranks']} ranks, "
      f"{r['communication_bytes']} bytes sent, certificate {max(r['certificate'][k] for k in ('equilibrium','penetration','tension','complementarity')):.1e}")
PY
