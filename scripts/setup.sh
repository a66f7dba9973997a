#!/usr/bin/env bash
# Installs the Debian 12 packages untangle needs (only those missing) and builds it into build/.
# Idempotent: run it again at any time; it installs nothing and rebuilds only what changed.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

# What each package is for: README.md, section "Dependencies".
packages=(
  build-essential     # C++ compiler, make
  cmake               # build system
  libcgal-dev         # exact predicates, box intersection, reference routines (tests, bench)
  libgmp-dev          # exact rationals behind CGAL (symbolic perturbation)
  libmpfr-dev         # CGAL's number types link it
  libboost-dev        # CGAL is built on Boost headers
  libeigen3-dev       # linear algebra (CGAL, displacement stage)
  libcli11-dev        # command line
  libassimp-dev       # mesh file formats
  libtbb-dev          # parallel narrow phase (oneTBB)
  nlohmann-json3-dev  # JSON reports
  libstb-dev          # render: PNG encoder (stb_image_write) and the legend's font (stb_easy_font)
  libgtest-dev        # tests (GoogleTest)
  libbenchmark-dev    # benchmarks (Google Benchmark)
  libcgal-demo        # the cow mesh (data/meshes/cow.off) used by tests and benchmarks
  assimp-testmodels   # real files in many formats for robustness tests
  groff-base          # renders the man page in its test
  parallel            # GNU parallel: runs `batch --emit parallel`'s script in its test
)
# The tests behind flags (README, "Tests behind flags") need more, installed only with their flag.
if [[ "${UNTANGLE_WITH_SLURM:-0}" == "1" || "${UNTANGLE_SLURM_TEST:-0}" == "1" ]]; then
  packages+=(
    munge             # authentication of the loopback Slurm cluster (scripts/slurm/)
    slurm-wlm         # slurmctld, slurmd, sbatch for tests/slurm/run_array_test.sh
  )
fi
if [[ "${UNTANGLE_WITH_BROWSER:-0}" == "1" || "${UNTANGLE_BROWSER_TEST:-0}" == "1" ]]; then
  packages+=(
    chromium          # headless page checks (tests/browser/check_page.py)
    python3           # check_page.py speaks the DevTools protocol to chromium
  )
fi
# The Blender comparison (bench/blender/cloth_vs_blender.sh), a benchmark never run by CI.
if [[ "${UNTANGLE_WITH_BLENDER:-0}" == "1" ]]; then
  packages+=(
    blender           # Blender's cloth against untangle simulate (docs/CONTRIBUTING.md)
  )
fi

sudo_cmd=()
if [[ "$(id -u)" -ne 0 ]]; then
  if ! command -v sudo > /dev/null; then
    echo "error: not root and sudo is not installed; run scripts/setup.sh as root" >&2
    exit 1
  fi
  sudo_cmd=(sudo)
fi

missing=()
for package in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$package" 2> /dev/null || true)"
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$package")
  fi
done

if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}" >&2
  "${sudo_cmd[@]}" apt-get update
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} Debian packages are installed" >&2
fi

# Minimal images (dpkg path-exclude /usr/share/doc/*) drop the archive holding the cow. Restore it
# from the package file so that the tests and benchmarks that use the cow run instead of skipping.
cow_tarball=/usr/share/doc/libcgal-demo/data.tar.gz
if [[ ! -e "$cow_tarball" ]]; then
  echo "setup: $cow_tarball is missing (documentation excluded?); restoring it" >&2
  shopt -s nullglob
  debs=(/var/cache/apt/archives/libcgal-demo_*.deb)
  workdir="$(mktemp -d)"
  trap 'rm -rf "$workdir"' EXIT
  if ((${#debs[@]} == 0)); then
    (cd "$workdir" && apt-get download libcgal-demo)
    debs=("$workdir"/libcgal-demo_*.deb)
  fi
  deb="${debs[0]}"
  dpkg-deb --fsys-tarfile "$deb" |
    "${sudo_cmd[@]}" tar -x -C / ./usr/share/doc/libcgal-demo ./usr/share/doc/libcgal-dev/data.tar.gz
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
