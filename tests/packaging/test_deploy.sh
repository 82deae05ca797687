#!/usr/bin/env bash
# Tests cross-toolchain/deploy.sh without a board: ssh and scp are stubs that log what they are asked to do and
# play a board (its architecture and whether the service starts are set per case). The package is a tiny
# armhf .deb made here. Exits 1 when any case fails.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
deploy="$root/cross-toolchain/deploy.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

mkdir -p "$work/pkg/DEBIAN"
printf 'Package: slambooster\nVersion: 9.8.7\nArchitecture: armhf\nMaintainer: t <t@example.org>\nDescription: t\n' \
  >"$work/pkg/DEBIAN/control"
dpkg-deb --root-owner-group -b "$work/pkg" "$work/slambooster_9.8.7_armhf.deb" >/dev/null
deb="$work/slambooster_9.8.7_armhf.deb"

mkdir -p "$work/bin"
cat >"$work/bin/ssh" <<EOF
#!/bin/sh
echo "ssh \$*" >>"$work/log"
case "\$*" in
  *"dpkg --print-architecture"*) echo "\$BOARD_ARCH" ;;
  *"systemctl restart"*) exit "\$RESTART_RC" ;;
  *"is-active"*) exit "\$RESTART_RC" ;;
  *"apt-get install"*) exit "\$INSTALL_RC" ;;
esac
exit 0
EOF
printf '#!/bin/sh\necho "scp $*" >>"%s/log"\n' "$work" >"$work/bin/scp"
chmod +x "$work/bin/ssh" "$work/bin/scp"

run() { # board_arch restart_rc args... -> $rc, $log   (INSTALL_RC: exit of apt-get install on the board)
  : >"$work/log"
  INSTALL_RC=${INSTALL_RC:-0} BOARD_ARCH=$1 RESTART_RC=$2 PATH="$work/bin:$PATH" bash "$deploy" "${@:3}" >"$work/out" 2>&1
  rc=$?
  log=$(cat "$work/log")
}
expect() { grep -qF -- "$1" <<<"$log" || fail "$case: expected a call '$1'; calls were: $log"; }
refuse() { ! grep -qF -- "$1" <<<"$log" || fail "$case: unexpected call '$1'; calls were: $log"; }

case="armhf board, defaults"
run armhf 0 odroid@xu4 "$deb"
[ $rc -eq 0 ] || fail "$case: exit $rc: $(cat "$work/out")"
expect "ssh odroid@xu4 dpkg --print-architecture"
expect "scp -q $deb odroid@xu4:/tmp/slambooster_9.8.7_armhf.deb"
expect "ssh odroid@xu4 sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold /tmp/slambooster_9.8.7_armhf.deb"
expect "ssh odroid@xu4 sudo systemctl restart slambooster.service"
refuse "systemctl enable"
[ "$(grep -n 'apt-get install' <<<"$log" | cut -d: -f1)" -lt "$(grep -n 'restart' <<<"$log" | cut -d: -f1)" ] ||
  fail "$case: restart before install: $log"

case="root on the board, --enable"
run armhf 0 --enable root@xu4 "$deb"
[ $rc -eq 0 ] || fail "$case: exit $rc"
expect "ssh root@xu4 env DEBIAN_FRONTEND=noninteractive apt-get install"
expect "ssh root@xu4 systemctl enable slambooster.service"

case="--no-restart"
run armhf 0 --no-restart odroid@xu4 "$deb"
[ $rc -eq 0 ] || fail "$case: exit $rc"
expect "sudo env DEBIAN_FRONTEND=noninteractive apt-get install"
refuse "systemctl restart"

case="amd64 host instead of the board"
run amd64 0 odroid@pc "$deb"
[ $rc -eq 1 ] || fail "$case: exit $rc, expected 1"
refuse "scp"
grep -q "is amd64, the package is armhf" "$work/out" || fail "$case: message: $(cat "$work/out")"

case="service fails to start"
run armhf 1 odroid@xu4 "$deb"
[ $rc -eq 1 ] || fail "$case: exit $rc, expected 1"
grep -q "journalctl -u slambooster" "$work/out" || fail "$case: message: $(cat "$work/out")"

case="install fails on the board (e.g. a dependency the board's archive lacks)"
INSTALL_RC=100 run armhf 0 odroid@xu4 "$deb"
[ $rc -eq 1 ] || fail "$case: exit $rc, expected 1"
refuse "systemctl restart"
grep -q "installing failed" "$work/out" || fail "$case: message: $(cat "$work/out")"

case="no USER@"
run armhf 0 xu4 "$deb"
[ $rc -eq 2 ] || fail "$case: exit $rc, expected 2"
refuse "ssh"

case="missing package"
run armhf 0 odroid@xu4 "$work/nope.deb"
[ $rc -eq 1 ] || fail "$case: exit $rc, expected 1"
grep -q "build_deb.sh" "$work/out" || fail "$case: message: $(cat "$work/out")"

echo "test_deploy: $failures failed"
[ "$failures" -eq 0 ]
