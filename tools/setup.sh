#!/usr/bin/env bash
# Installs the Debian packages gaitlab builds, tests, benchmarks and packages with (dpkg-dev and
# file: dpkg-shlibdeps computes the .deb's dependencies, tools/package.sh; lua5.3, lua5.1 and
# luajit: the tests check that `require "gaitlab"` refuses them; OpenMPI: `mpirun gaitlab
# optimize` spreads evaluations over ranks, optional for the build), and the viewer page's npm
# packages (three.js, uPlot, playwright-core for the browser tests: `npm ci` in viewer/web,
# pinned by its package-lock.json); `tools/setup.sh fuzz` also installs clang and libFuzzer
# (tools/fuzz.sh).
# Idempotent: prints nothing and installs nothing when everything is already there.
set -euo pipefail

packages=(
    cmake g++ ninja-build pkg-config
    liblua5.4-dev lua5.4
    lua5.3 lua5.1 luajit
    libbullet-dev libfmt-dev libtinyxml2-dev libpng-dev
    catch2 libcli11-dev libbenchmark-dev libedit-dev nlohmann-json3-dev libeigen3-dev
    liburdfdom-tools gnuplot-nox valgrind tmux dpkg-dev file
    libcpp-httplib-dev chromium
    libopenmpi-dev openmpi-bin time
)
# Node.js and npm build the viewer's page; a Node.js from elsewhere that brings its own npm will do
command -v npm >/dev/null || packages+=(nodejs npm)

if [ "${1:-}" = fuzz ]; then
    packages+=(clang libclang-rt-14-dev)
fi

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if [ ${#missing[@]} -gt 0 ]; then
    echo "gaitlab setup: installing ${missing[*]}" >&2
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null || {
            echo "gaitlab setup: run as root or install sudo" >&2
            exit 1
        }
        sudo="sudo"
    fi
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# the viewer's npm packages, again whenever package-lock.json changes (a stamp holds its hash)
web="$(cd "$(dirname "$0")/.." && pwd)/viewer/web"
stamp="$web/node_modules/.gaitlab-lock-hash"
hash=$(sha256sum "$web/package-lock.json" | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null)" != "$hash" ]; then
    echo "gaitlab setup: npm ci in viewer/web" >&2
    (cd "$web" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
    echo "$hash" > "$stamp"
fi
