#!/usr/bin/env bash
# pip_installed.sh SOURCE_DIR WORK_DIR [CMAKE_DEFINE=VALUE...] (ctest python.pip_installed)
#
# The Python suite against the package as pip installs it: a wheel built by scikit-build-core from
# .venv (scripts/install-deps; no build isolation) with its CMake build in WORK_DIR, installed into
# a fresh venv of /usr/bin/python3 that sees Debian's numpy, scipy and pytest and gets the pins of
# python/requirements-dev.txt. pytest runs from inside that venv, without PYTHONPATH; the tests
# check that acdf and the acdf program are the venv's.
set -euo pipefail
source_dir=$1
work=$2
shift 2
settings=()
for define in "$@"; do settings+=("--config-settings=cmake.define.$define"); done

builder=$source_dir/.venv/bin/python
if [[ ! -x $builder ]]; then
  echo "pip_installed.sh: no $builder (scripts/install-deps makes it)" >&2
  exit 1
fi
rm -rf "$work/dist" "$work/venv"
"$builder" -m pip wheel --quiet --no-deps --no-build-isolation --disable-pip-version-check \
  --wheel-dir "$work/dist" --config-settings=build-dir="$work" "${settings[@]}" "$source_dir"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip install --quiet --no-deps --no-index --disable-pip-version-check "$work"/dist/acdf-*.whl
# The PyPI packages the tests use beside the package, as in .venv (from pip's cache once downloaded).
"$work/venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$source_dir/python/requirements-dev.txt"

venv=$work/venv
site=$("$venv/bin/python" -c "import sysconfig; print(sysconfig.get_path('platlib'))")
cd "$venv"
unset PYTHONPATH
export ACDF_PACKAGE_DIR=$site/acdf ACDF_PROGRAM=$venv/bin/acdf
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider "$source_dir/tests/python"
