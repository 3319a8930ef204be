#!/usr/bin/env bash
# Builds the Debian packages gaitlab_<version>_<arch>.deb and gaitlab-dev_<version>_<arch>.deb
# into build/packages/ (docs/install.md): installs what the build needs (tools/setup.sh),
# configures build/ for the prefix /usr (the libraries then go to /usr/lib/<multiarch>, as
# Debian's do; nothing is recompiled for it), builds and runs cpack.
# Usage: tools/package.sh [extra cmake -D options]; BUILD_DIR (default build) selects the build
# tree, the packages go to BUILD_DIR/packages/.
# The Maintainer field is "$DEBFULLNAME <$DEBEMAIL>" when both are set, as for Debian's tools.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
"$root/tools/setup.sh"

# dpkg-shlibdeps (dpkg-dev) and file find the shared libraries the packages depend on: without
# them CPack would make a package that installs but cannot start
for tool in dpkg-shlibdeps dpkg-deb file; do
    if ! command -v "$tool" >/dev/null; then
        echo "tools/package.sh: '$tool' not found: it is needed to compute the packages'" \
             "dependencies. Install it (apt install dpkg-dev file) and run tools/package.sh again." >&2
        exit 1
    fi
done

options=(-DCMAKE_INSTALL_PREFIX=/usr)
if [ -n "${DEBFULLNAME:-}" ] && [ -n "${DEBEMAIL:-}" ]; then
    options+=("-DGAITLAB_PACKAGE_MAINTAINER=$DEBFULLNAME <$DEBEMAIL>")
fi
generator=()
if [ ! -f "$build/CMakeCache.txt" ]; then
    generator=(-DCMAKE_BUILD_TYPE=Release)
    command -v ninja >/dev/null && generator+=(-G Ninja)
fi
cmake -S "$root" -B "$build" "${generator[@]}" "${options[@]}" "$@" >/dev/null
cmake --build "$build" --target gaitlab --parallel "$(nproc)"
rm -f "$build"/packages/gaitlab*.deb
(cd "$build" && cpack -G DEB -B "$build/packages" >/dev/null)
echo "tools/package.sh: made"
ls -1 "$build"/packages/*.deb
