#!/usr/bin/env bash
# build_wheel.sh SOURCE_DIR WORK_DIR [CMAKE_DEFINE=VALUE...] (ctest python.wheel, the fixture of the
# python.pip_installed tests)
#
# The wheel `pip install` builds, into WORK_DIR/dist: scikit-build-core from .venv (scripts/install-deps;
# no build isolation, the pins of pyproject.toml) with its CMake build in WORK_DIR.
set -euo pipefail
source_dir=$1
work=$2
shift 2
settings=()
for define in "$@"; do settings+=("--config-settings=cmake.define.$define"); done

builder=$source_dir/.venv/bin/python
if [[ ! -x $builder ]]; then
  echo "build_wheel.sh: no $builder (scripts/install-deps makes it)" >&2
  exit 1
fi
rm -rf "$work/dist"
"$builder" -m pip wheel --quiet --no-deps --no-build-isolation --disable-pip-version-check \
  --wheel-dir "$work/dist" --config-settings=build-dir="$work" "${settings[@]}" "$source_dir"
