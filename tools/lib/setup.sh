# Shared by tools/run and tools/test: install missing Debian packages, configure, build.
# Sourced, not executed. Builds the `release` preset into build/ (incrementally).

facet_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"

# Every package the build and the test suite need on a fresh Debian 12 machine.
facet_packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libxsimd-dev libtbb-dev
  libgtest-dev libbenchmark-dev
  libtinyobjloader-dev nlohmann-json3-dev libpng-dev libjpeg62-turbo-dev libstb-dev libembree-dev
  libmeshoptimizer-dev libdraco-dev libcli11-dev libopenexr-dev
)

# Extra packages for one command may be given as arguments (tools/charts: python3-matplotlib).
facet_install_packages() {
  local missing=() pkg
  for pkg in "${facet_packages[@]}" "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$pkg")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "facet: missing Debian packages. Install them with:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    return 1
  fi
  echo "facet: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq || return 1
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null || return 1
}

# facet_build [TARGET...]: configure the release preset if needed and build the named targets
# (default: everything; tools/run asks for the `facet` program alone, so that a newcomer's first
# picture does not wait for the tests and benchmarks).
facet_build() {
  local build_dir="$facet_root/build"
  # build.ninja, not CMakeCache.txt: a configure that failed (a package missing) leaves a cache
  # but no build files, and must run again.
  if [ ! -f "$build_dir/build.ninja" ]; then
    cmake --preset release -S "$facet_root" >/dev/null || return 1
  fi
  local targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$build_dir" --parallel "$(nproc)" "${targets[@]}" || return 1
}

# OSMesa (libosmesa6-dev) is optional: a build configured before it was installed must look for
# it again to build the llvmpipe comparison.
facet_refresh_osmesa() {
  local cache="$facet_root/build/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q "OSMESA_FOUND:INTERNAL=1" "$cache"; then
    cmake "$facet_root/build" >/dev/null
  fi
}
