#!/usr/bin/env bash
# The CI entry point: system packages, build, tests, MPI tests.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Open MPI refuses to run as root and binds ranks to cores unless told otherwise.
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_hwloc_base_binding_policy=none

echo "==> [1/4] setup: system packages and toolchain"
bash ci/setup.sh
# setup.sh checks cargo in its own shell; put it on this shell's PATH too.
if ! command -v cargo >/dev/null 2>&1 && [ -f "$HOME/.cargo/env" ]; then
    # shellcheck disable=SC1091
    . "$HOME/.cargo/env"
fi

echo "==> [2/4] build: cargo build --release --features mpi --workspace --all-targets"
cargo build --release --features mpi --workspace --all-targets

echo "==> [3/4] test: cargo test --release --features mpi --workspace"
cargo test --release --features mpi --workspace

echo "==> [4/4] MPI tests"
if [ -f ci/mpi-tests.sh ]; then
    bash ci/mpi-tests.sh
else
    echo "no MPI tests yet"
fi

echo "==> CI passed"
