#!/usr/bin/env bash
# Builds the Debian package from a configured and built folder, installs it with apt (its
# dependencies resolved from Debian's archive), smoke-tests the installed program and removes
# the package again.
#   packaging/deb/build-and-check.sh BUILD_DIR
set -euo pipefail
build=$(readlink -f "${1:?usage: $0 BUILD_DIR}")
src=$(cd "$(dirname "$0")/../.." && pwd)

echo "== Debian package"
rm -f "$build"/atelier-cli_*.deb "$build"/atelier_*.deb
(cd "$build" && cpack -G DEB >/dev/null)
deb=$(ls "$build"/atelier-cli_*.deb)
gui=$(ls "$build"/atelier_*.deb)
for package in "$deb" "$gui"; do
    dpkg-deb --info "$package" | sed -n '/Package:/p;/Depends:/p;/Installed-Size:/p'
done
dpkg-deb --contents "$deb" | awk '{print $6}' >"$build/deb-contents.txt"
dpkg-deb --contents "$gui" | awk '{print $6}' >>"$build/deb-contents.txt"
for path in ./usr/bin/atelier-cli ./usr/share/man/man1/atelier-cli.1.gz \
    ./usr/share/atelier/garments/tshirt.atelier ./usr/share/atelier/materials/fabrics.json \
    ./usr/share/mime/packages/atelier.xml ./usr/share/atelier/batch/atelier-array.sbatch \
    ./usr/bin/atelier ./usr/share/applications/atelier.desktop \
    ./usr/share/icons/hicolor/scalable/apps/atelier.svg; do
    grep -qx "$path" "$build/deb-contents.txt" || { echo "FAIL: $path not in the packages"; exit 1; }
done
dpkg-deb --info "$deb" | grep -q "Depends:.*libqt6" &&
    { echo "FAIL: atelier-cli must not need Qt"; exit 1; }

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get install -y -qq "$deb" "$gui" >/dev/null
trap '$SUDO apt-get remove -y -qq atelier atelier-cli >/dev/null' EXIT

echo "== Installed atelier-cli and atelier"
/usr/bin/atelier-cli --version
QT_QPA_PLATFORM=offscreen /usr/bin/atelier --version | grep -q "atelier 0.1.0" ||
    { echo "FAIL: atelier --version"; exit 1; }
# Every subcommand is in the man page.
for cmd in $(/usr/bin/atelier-cli --help | awk '/^Subcommands:/{on=1; next} on && NF {print $1}'); do
    zcat /usr/share/man/man1/atelier-cli.1.gz | grep -q "^\.B $cmd\$" ||
        { echo "FAIL: the man page does not describe '$cmd'"; exit 1; }
done
work=$(mktemp -d)
trap 'cd /; rm -rf "$work"; $SUDO apt-get remove -y -qq atelier atelier-cli >/dev/null' EXIT
cd "$work"
/usr/bin/atelier-cli drape /usr/share/atelier/garments/skirt.atelier --particle-distance 40 \
    --time-limit 0.3 --threads 1 --out skirt.obj --report skirt.json
test -s skirt.obj && test -s skirt.body.obj && grep -q '"finite": true' skirt.json
if /usr/bin/atelier-cli render skirt.obj --out skirt.png --size 128x128 2>render.err; then
    test -s skirt.png
else
    # No EGL here: the installed program must say so clearly rather than write a black picture.
    grep -q "EGL" render.err || { cat render.err; exit 1; }
    echo "(render: no EGL on this machine: $(head -1 render.err))"
fi
echo "PASS: $(basename "$deb") and $(basename "$gui") install; atelier-cli drapes and draws"
