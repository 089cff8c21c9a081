#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief One idempotent set-up for a fresh Debian bookworm machine: installs every Debian package
#        telesphere needs, configures and builds, then runs what was asked.
#
#   bash setup.sh deps     install the Debian packages only
#   bash setup.sh          install + build the programs (Release, build/bin)
#   bash setup.sh demo     install + build + run the main job on the embedded default
#   bash setup.sh test     install + build the programs as `build` does, then the test tree
#                          (ASan+UBSan, build-test/) + ctest (which runs the demo on build/ too)
#
# Needs root (or sudo) for apt-get; everything else runs as the calling user.
set -euo pipefail
cd "$(dirname "$0")"
what=${1:-build}
case "$what" in
  deps|build|demo|test) ;;
  *) echo "usage: bash setup.sh [deps|build|demo|test]" >&2; exit 2 ;;
esac

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config ccache git
  # maths, calibration, vision
  libeigen3-dev libceres-dev libopencv-dev libopencv-contrib-dev
  # cameras
  libaravis-dev aravis-tools iproute2
  # rendering and XR
  libglm-dev libopenxr-dev libopenxr-loader1 libegl-dev libgl-dev libgles-dev libglfw3-dev
  libegl-mesa0 libgl1-mesa-dri libpng-dev
  # desktop mode and mirror window, tested on a virtual X server (key and mouse input via XTest)
  xvfb libxtst-dev xdotool
  # console
  qt6-base-dev libqcustomplot-dev libsqlite3-dev libqt6sql6-sqlite
  # video path and link
  libturbojpeg0-dev libjpeg-turbo-progs libzmq3-dev cppzmq-dev libsodium-dev libprotobuf-dev protobuf-compiler
  # H.264 and HEVC beside MJPEG (FFmpeg's libavcodec: x264, x265, NVENC where a GPU is)
  libavcodec-dev libavutil-dev
  # the Internet link's forward error correction (Reed–Solomon erasure code)
  libisal-dev
  # SRT, the transport `telesphere-bench transport` compares the media path with (the GnuTLS
  # flavour FFmpeg already brings in)
  libsrt-gnutls-dev
  # session recordings (MCAP chunk compression)
  libzstd-dev liblz4-dev zlib1g-dev
  # files, command lines, logging
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  # tests, benchmarks and fuzzing (libFuzzer comes with clang's runtime)
  libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-14-dev
  # a real OpenXR runtime for the integration test: Debian trixie's Monado in a side root
  debootstrap zstd
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "setup: all ${#packages[@]} Debian packages present"
fi

jobs=$(nproc)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)

# The programs in Release, not unity: what README's first command builds and runs. The test command
# builds the very same tree first, so a translation unit that only compiles inside a unity batch of
# the test tree (a missing include) turns CI red instead of a newcomer's first step.
build_programs() {
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
  cmake --build build -j "$jobs" --target telesphere-programs
}

case "$what" in
  deps)
    ;;
  build|demo)
    build_programs
    if [[ $what == demo ]]; then
      exec bash app/demo.sh build
    fi
    ;;
  test)
    build_programs
    werror=OFF
    [[ -n ${CI:-} ]] && werror=ON
    # Line tables only (-g1): all a sanitizer report needs for file:line, and a third less compile
    # time than -g. Three UBSan checks that instrument every pointer use are left out
    # (TELESPHERE_UBSAN_SKIP in CMakeLists.txt): another third (tests/README.md#ci-from-nothing).
    # The demo tree built above also runs the benchmarks' smoke runs and the calibration tests'
    # simulated robot (TELESPHERE_USE_DEMO_TREE).
    cmake -S . -B build-test -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DTELESPHERE_SANITIZE=ON -DTELESPHERE_UBSAN_SKIP="alignment,null,pointer-overflow" \
      -DTELESPHERE_WERROR="$werror" -DTELESPHERE_UNITY=ON \
      -DTELESPHERE_DEMO_TREE="$PWD/build" -DTELESPHERE_USE_DEMO_TREE=ON "${launcher[@]}"
    cmake --build build-test -j "$jobs"
    # Monado (Debian trixie) for the OpenXR integration test, built once and cached outside the
    # repo (tests/xr/monado/README.md). Needs root the first time; without it the test is skipped.
    monado_root=${TELESPHERE_MONADO_ROOT:-${TELESPHERE_MONADO_CACHE:-/var/cache/telesphere}/monado-trixie}
    if sh tests/xr/monado/build_trixie_root.sh "$monado_root"; then
      export TELESPHERE_MONADO_ROOT=$monado_root
    elif [[ -n ${CI:-} ]]; then
      echo "setup: CI needs the Monado root for the OpenXR integration test (see above)" >&2
      exit 1
    else
      echo "setup: no Monado root: the OpenXR integration test will be skipped" >&2
    fi
    ctest --test-dir build-test --output-on-failure -j "$jobs"
    # libFuzzer targets need clang: a separate tree, each target fuzzed briefly from its corpus.
    CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DTELESPHERE_SANITIZE=ON -DTELESPHERE_FUZZ=ON -DTELESPHERE_COMPONENTS="robot/link;robot/record" \
      -DTELESPHERE_FUZZ_SECONDS="${TELESPHERE_FUZZ_SECONDS:-20}" "${launcher[@]}"
    cmake --build build-fuzz -j "$jobs" --target telesphere-fuzz-targets
    ctest --test-dir build-fuzz --output-on-failure -L fuzz -j "$jobs"
    ;;
esac
