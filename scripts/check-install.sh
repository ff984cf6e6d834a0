#!/usr/bin/env bash
# Checks the install tree and the Debian package of a build: `cmake --install` into a
# scratch DESTDIR (prefix /usr, as the package has it) holds the programs, the configs in
# /etc/omniview, the robot model and a systemd unit that `systemd-analyze verify` accepts;
# with --deb, `cpack -G DEB` makes a package with the same files and maintainer scripts.
#
#   bash scripts/check-install.sh [BUILD_DIR] [--deb]
#
# Needs a build with omniviewd and omniview built. No root, no running systemd:
# verify runs on the scratch tree (skipped, saying so, where systemd-analyze is missing).
set -euo pipefail

build=build
deb=0
for arg in "$@"; do
  case "$arg" in
    --deb) deb=1 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) build=$arg ;;
  esac
done
build=$(cd "$build" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
root=$scratch/root

fail() { echo "check-install: FAIL: $*" >&2; exit 1; }

DESTDIR=$root cmake --install "$build" --prefix /usr > "$scratch/install.log" ||
  { cat "$scratch/install.log" >&2; fail "cmake --install failed"; }

expected=(
  usr/bin/omniviewd
  usr/bin/omniview
  etc/omniview/omniviewd.yaml
  etc/omniview/spot.yaml
  etc/omniview/spot/README
  etc/omniview/insta360.yaml
  etc/omniview/insta360/air_calibration.yaml
  etc/omniview/examples/dual_fisheye/rig.yaml
  etc/omniview/examples/dual_fisheye/front.jpg
  etc/omniview/examples/views/front_perspective.yaml
  etc/omniview/robots/spot/spot_like.urdf
  usr/lib/systemd/system/omniviewd.service
  usr/lib/sysusers.d/omniview.conf
  usr/share/doc/omniview/API.md
  usr/share/omniview/console/index.html
  usr/share/omniview/console/js/main.js
)
for f in "${expected[@]}"; do
  [ -e "$root/$f" ] || fail "the install tree lacks $f"
done
[ ! -e "$root/usr/bin/spot-mock" ] || fail "the install tree ships spot-mock (a test tool)"
grep -q 'out/spot-mock' "$root/etc/omniview/spot.yaml" && fail "the installed spot.yaml names the source tree's out/spot-mock"
for f in usr/bin/omniviewd usr/bin/omniview; do
  [ -x "$root/$f" ] || fail "$f is not executable"
done
# Nothing outside the places a package may use.
stray=$(cd "$root" && find . -type f | grep -v -E '^\./(usr/(bin|lib/systemd/system|lib/sysusers\.d|share/doc/omniview|share/omniview/console)|etc/omniview)/' || true)
[ -z "$stray" ] || fail "files outside the expected folders: $stray"

unit=$root/usr/lib/systemd/system/omniviewd.service
grep -q '^ExecStart=/usr/bin/omniviewd --config /etc/omniview/omniviewd.yaml$' "$unit" || fail "ExecStart in $unit"
grep -q '^User=omniview$' "$unit" || fail "the unit does not run as the user omniview"
grep -q '^u omniview ' "$root/usr/lib/sysusers.d/omniview.conf" || fail "sysusers.d entry"

# The installed daemon accepts the installed configs (their relative paths resolve in /etc/omniview).
for config in omniviewd.yaml insta360.yaml; do
  "$root/usr/bin/omniviewd" --check --config "$root/etc/omniview/$config" > "$scratch/check.log" 2>&1 ||
    { cat "$scratch/check.log" >&2; fail "omniviewd --check rejects the installed $config"; }
done

if command -v systemd-analyze > /dev/null; then
  # verify wants the programs a unit names to exist: check a copy that names them in the tree.
  mkdir -p "$scratch/units"
  sed -e "s|=/usr/bin/|=$root/usr/bin/|g" -e "s|/etc/omniview/|$root/etc/omniview/|g" "$unit" \
    > "$scratch/units/omniviewd.service"
  if ! SYSTEMD_LOG_LEVEL=notice systemd-analyze verify --man=no "$scratch/units/omniviewd.service" \
      > "$scratch/verify.log" 2>&1; then
    cat "$scratch/verify.log" >&2
    fail "systemd-analyze verify rejects omniviewd.service"
  fi
  # Warnings about the host (no such user yet, no running systemd) are not the unit's fault.
  if grep -v -i -E 'user|group|not booted|System has not been booted|Failed to (connect|setup)' \
      "$scratch/verify.log" | grep -q .; then
    cat "$scratch/verify.log" >&2
    fail "systemd-analyze verify has remarks about omniviewd.service"
  fi
  echo "check-install: systemd-analyze verify accepts omniviewd.service"
else
  echo "check-install: systemd-analyze is not installed: skipped verifying the unit (apt-get install systemd)"
fi

if [ "$deb" = 1 ]; then
  (cd "$scratch" && cpack -G DEB --config "$build/CPackConfig.cmake" > cpack.log 2>&1) ||
    { cat "$scratch/cpack.log" >&2; fail "cpack -G DEB failed"; }
  package=$(ls "$scratch"/*.deb)
  dpkg-deb --contents "$package" | awk '{print $6}' | sed 's|^\./||' > "$scratch/deb-files"
  for f in "${expected[@]}"; do
    grep -qx "$f" "$scratch/deb-files" || fail "the package lacks $f"
  done
  mkdir "$scratch/control"
  dpkg-deb --control "$package" "$scratch/control"
  for f in postinst prerm postrm conffiles; do
    [ -e "$scratch/control/$f" ] || fail "the package has no $f"
  done
  # Every file in /etc is a conffile: dpkg keeps an admin's edits across upgrades.
  grep '^etc/' "$scratch/deb-files" | grep -v '/$' | sed 's|^|/|' | sort > "$scratch/etc-files"
  sort "$scratch/control/conffiles" | diff -u "$scratch/etc-files" - > "$scratch/conffiles.diff" ||
    { cat "$scratch/conffiles.diff" >&2; fail "the conffiles differ from the files in /etc (-: not a conffile)"; }
  grep -q 'systemd-sysusers omniview.conf' "$scratch/control/postinst" || fail "postinst does not create the user"
  depends=$(dpkg-deb --field "$package" Depends)
  case "$depends" in *libgrpc*) ;; *) fail "Depends lacks the gRPC library: $depends" ;; esac
  echo "check-install: $(basename "$package"): $(wc -l < "$scratch/deb-files") entries, Depends: $depends"
fi
echo "check-install: OK"
