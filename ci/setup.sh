#!/usr/bin/env bash
# Install the system packages the build, the MPI tests and the progress test
# (bsdutils: `script`, a pseudo-terminal) need, only when missing.
# Idempotent and quiet when everything is already there.
set -euo pipefail

packages=(libopenmpi-dev openmpi-bin libclang-dev bsdutils)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg -s "$p" >/dev/null 2>&1; then
        missing+=("$p")
    fi
done

if [ "${#missing[@]}" -gt 0 ]; then
    echo "ci/setup.sh: installing missing packages: ${missing[*]}"
    as_root() {
        if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
    }
    as_root apt-get update
    as_root env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${missing[@]}"
fi

# Python's meshio reads the VTU files back in tests/integration/solids.rs (an
# independent reader beside vtkio).
if ! python3 -c "import meshio" >/dev/null 2>&1; then
    echo "ci/setup.sh: installing meshio (pip)"
    python3 -m pip install --quiet --disable-pip-version-check meshio
fi

# cargo on PATH (rustup installs put it in ~/.cargo/bin).
if ! command -v cargo >/dev/null 2>&1 && [ -f "$HOME/.cargo/env" ]; then
    # shellcheck disable=SC1091
    . "$HOME/.cargo/env"
fi
if ! command -v cargo >/dev/null 2>&1; then
    echo "ci/setup.sh: cargo not found on PATH" >&2
    exit 1
fi
