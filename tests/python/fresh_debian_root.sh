#!/usr/bin/env bash
# fresh_debian_root.sh SOURCE_DIR WORK_DIR WHEEL_DIR (make test-wheel-portable; root, debootstrap)
#
# The repaired wheel on a Linux that has nothing of acdf's build: a Debian 12 root with only Python
# and pip (debootstrap --variant=minbase, python3-venv; no -dev package, no OpenImageIO) and
# libatomic1, which Mitsuba's drjit 1.5 links without carrying it, in WORK_DIR. The wheel from
# WHEEL_DIR and mitsuba==3.9.1 are pip-installed into a venv there, then `import acdf` samples the
# bundled sunset map, the acdf program writes a sky and materials (one from the fits the wheel
# carries), and examples/mitsuba/render.py renders them in scalar_rgb. The base root and pip's
# downloads are kept in WORK_DIR between runs; each run starts from a fresh copy of the base.
set -euo pipefail
source_dir=$(cd "$1" && pwd)
work=$2
wheel_dir=$3
mirror=${DEBIAN_MIRROR:-http://deb.debian.org/debian}

wheels=("$wheel_dir"/acdf-*manylinux*.whl)
if [[ ! -f ${wheels[0]} ]]; then
  echo "fresh_debian_root.sh: no repaired wheel in $wheel_dir (ctest -R python.wheel builds it)" >&2
  exit 1
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "fresh_debian_root.sh: needs root (debootstrap, chroot, mount)" >&2
  exit 1
fi

packages=python3,python3-venv,libatomic1
base=$work/bookworm-${packages//,/-}
if [[ ! -f $base/.complete ]]; then
  rm -rf "$base"
  mkdir -p "$work"
  debootstrap --variant=minbase --include="$packages" bookworm "$base" "$mirror"
  touch "$base/.complete"
fi

root=$work/root
mounts=()
cleanup() {
  local i
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount -l "${mounts[i]}" 2>/dev/null || true; done
}
trap cleanup EXIT
# A run killed before its trap leaves its mounts behind: never delete through them (/dev is the
# host's).
for dir in "$root/root/.cache/pip" "$root/dev" "$root/proc"; do
  if mountpoint -q "$dir" 2>/dev/null; then umount -l "$dir"; fi
done
rm -rf --one-file-system "$root"
cp -a "$base" "$root"
for dir in proc dev; do
  mount --bind "/$dir" "$root/$dir"
  mounts+=("$root/$dir")
done
# pip's downloads (the wheels of mitsuba, drjit, numpy) persist across runs where the responses may
# be cached.
mkdir -p "$work/pip-cache" "$root/root/.cache/pip"
mount --bind "$work/pip-cache" "$root/root/.cache/pip"
mounts+=("$root/root/.cache/pip")
cp /etc/resolv.conf "$root/etc/resolv.conf"
# pip checks PyPI's certificate against the host's trust store (where a proxy that re-signs TLS has
# its CA); the base root has no ca-certificates package.
trust=()
if [[ -f /etc/ssl/certs/ca-certificates.crt ]]; then
  mkdir -p "$root/etc/ssl/certs"
  cp /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/"
  trust=(PIP_CERT=/etc/ssl/certs/ca-certificates.crt)
fi

mkdir -p "$root/test/wheels"
cp "${wheels[@]}" "$root/test/wheels/"
cp "$source_dir/data/envmaps/sunset_1024x512.exr" "$source_dir/examples/mitsuba/render.py" "$root/test/"
cat >"$root/test/run.sh" <<'INNER'
set -euo pipefail
cd /test
python3 -m venv venv
venv/bin/pip install --quiet --disable-pip-version-check wheels/acdf-*.whl mitsuba==3.9.1
venv/bin/pip check
venv/bin/python - <<'PY'
import numpy as np

import acdf

light = acdf.EnvironmentLight.load("sunset_1024x512.exr", strategy="adaptive")
dirs, radiance, pdf = light.sample(np.random.default_rng(1).random((100_000, 2), dtype=np.float32))
power = (radiance @ [0.2126, 0.7152, 0.0722] / pdf).mean()
assert np.all(pdf > 0) and np.allclose(np.linalg.norm(dirs, axis=1), 1), "bad samples"
print(f"acdf {acdf.__version__}: 1e5 adaptive samples of the sunset map, mean L/pdf {power:.4g}")
PY
venv/bin/acdf --version
venv/bin/acdf env-gen --preset sunset --width 64 --height 32 -o sky.exr
venv/bin/acdf rgl-gen --preset gold -o gold.bsdf
# The neural fits the wheel carries (there is no source tree to fall back on here).
venv/bin/acdf merl-gen --nbrdf nickel -o nickel.binary
venv/bin/python render.py sky.exr gold.bsdf gold.exr --variant scalar_rgb --size 32x24 --spp 4
venv/bin/python -c "import acdf; assert acdf.EnvironmentMap.load('gold.exr').pixel_power().sum() > 0, 'black render'"
INNER
chroot "$root" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root "${trust[@]}" bash /test/run.sh
echo "fresh_debian_root.sh: the wheel installs and runs in a fresh Debian 12 root"
