#!/usr/bin/env bash
# Installs the armhf package on a board over ssh and restarts the service.
#
#   cross-toolchain/deploy.sh [--no-restart] [--enable] USER@HOST [PACKAGE.deb]
#
#   PACKAGE.deb    default: the newest build-armhf/deb/slambooster_*_armhf.deb (cross-toolchain/build_deb.sh)
#   --no-restart   install only; the service keeps running the old binaries until restarted
#   --enable       also enable the service at boot (installing the package never does)
#
# Steps: checks that the board is armhf Debian, copies the package to /tmp on the board (scp), installs it
# with `apt-get install /tmp/<deb>` (dpkg -i plus the missing dependencies from the board's own archive;
# without a prompt, keeping an edited /etc/slambooster config and leaving the new default beside it as
# *.dpkg-dist), restarts slambooster.service, and prints its status. Exits non-zero when a step fails or the service is not active after the restart. SSH options (port,
# key) come from ~/.ssh/config. The remote user needs sudo unless it is root (asked for its password when run
# from a terminal).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
say() { echo "deploy: $*"; }
usage() { sed -n '4,9p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }

restart=1
enable=0
args=()
for a in "$@"; do
  case "$a" in
    --no-restart) restart=0 ;;
    --enable) enable=1 ;;
    -h|--help) usage ;;
    -*) say "unknown option $a" >&2; usage ;;
    *) args+=("$a") ;;
  esac
done
[ ${#args[@]} -ge 1 ] && [ ${#args[@]} -le 2 ] || usage
target=${args[0]}
[[ "$target" == *@* ]] || { say "give the board as USER@HOST (got '$target')" >&2; exit 2; }
deb=${args[1]:-$(ls -t "$root"/build-armhf/deb/slambooster_*_armhf.deb 2>/dev/null | head -n1 || true)}
if [ -z "$deb" ] || [ ! -f "$deb" ]; then
  say "no package ${deb:+at $deb }- build one with cross-toolchain/build_deb.sh" >&2
  exit 1
fi

user=${target%@*}
sudo=""
[ "$user" = root ] || sudo="sudo "
# A terminal for sudo's password prompt when there is one to offer (interactive use).
ssh_opts=()
[ -t 0 ] && [ -n "$sudo" ] && ssh_opts=(-t)
remote() { ssh "${ssh_opts[@]}" "$target" "$@"; }

board_arch=$(remote dpkg --print-architecture) || { say "cannot run dpkg on $target over ssh" >&2; exit 1; }
deb_arch=$(dpkg-deb -f "$deb" Architecture)
if [ "$board_arch" != "$deb_arch" ]; then
  say "$target is $board_arch, the package is $deb_arch; refusing to install" >&2
  exit 1
fi

name=$(basename "$deb")
say "copying $name to $target:/tmp/"
scp -q "$deb" "$target:/tmp/$name"
say "installing (apt-get install /tmp/$name: dpkg -i and its dependencies)"
if ! remote "${sudo}env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends" \
  "-o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold /tmp/$name"; then
  say "installing failed on $target (see above); the package stays in /tmp/$name there" >&2
  exit 1
fi
remote "rm -f /tmp/$name"
if [ "$enable" = 1 ]; then
  say "enabling slambooster.service at boot"
  remote "${sudo}systemctl enable slambooster.service"
fi
if [ "$restart" = 0 ]; then
  say "installed; not restarted (--no-restart)"
  exit 0
fi
say "restarting slambooster.service"
if ! remote "${sudo}systemctl restart slambooster.service"; then
  remote "${sudo}systemctl --no-pager status slambooster.service" || true
  say "the service did not start; see the status above and 'journalctl -u slambooster' on the board" >&2
  exit 1
fi
remote "${sudo}systemctl --no-pager status slambooster.service" || true
if ! remote "systemctl is-active --quiet slambooster.service"; then
  say "slambooster.service is not active; see 'journalctl -u slambooster' on the board" >&2
  exit 1
fi
say "done: $(dpkg-deb -f "$deb" Version) runs on $target"
