#!/usr/bin/env bash
# pip_installed.sh SOURCE_DIR WORK_DIR debian|pypi (ctest python.pip_installed, python.pip_installed_numpy2)
#
# The Python suite against the package as pip installs it: the wheel build_wheel.sh left in
# WORK_DIR/dist, installed into a fresh venv of /usr/bin/python3, with
#   debian: Debian's numpy 1.24, scipy and pytest (--system-site-packages) and the pins of
#           python/requirements-dev.txt;
#   pypi:   nothing of Debian's, the pins of python/requirements-numpy2.txt (PyPI's NumPy 2): what
#           `pip install acdf` gives a new user in `python3 -m venv`.
# pytest runs from inside that venv, without PYTHONPATH; the tests check that acdf and the acdf
# program are the venv's.
set -euo pipefail
source_dir=$1
work=$2
kind=$3
case $kind in
  debian) venv_flags=(--system-site-packages) requirements=$source_dir/python/requirements-dev.txt ;;
  pypi) venv_flags=() requirements=$source_dir/python/requirements-numpy2.txt ;;
  *) echo "pip_installed.sh: unknown environment '$kind' (debian or pypi)" >&2; exit 2 ;;
esac

venv=$work/venv-$kind
rm -rf "$venv"
/usr/bin/python3 -m venv "${venv_flags[@]}" "$venv"
"$venv/bin/python" -m pip install --quiet --no-deps --no-index --disable-pip-version-check "$work"/dist/acdf-*.whl
# The PyPI packages the tests use beside the package (from pip's cache once downloaded).
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements"
# The wheel's own requirements (numpy) must be met by what a clean environment has (Debian's site
# packages have unmet requirements of their own, e.g. pygobject's pycairo).
if [[ $kind == pypi ]]; then "$venv/bin/python" -m pip check; fi

site=$("$venv/bin/python" -c "import sysconfig; print(sysconfig.get_path('platlib'))")
cd "$venv"
unset PYTHONPATH
export ACDF_PACKAGE_DIR=$site/acdf ACDF_PROGRAM=$venv/bin/acdf
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider "$source_dir/tests/python"
