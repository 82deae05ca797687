#!/usr/bin/env bash
# Checks the slambooster .deb (cross-toolchain/packaging.cmake) as a user and dpkg will see it:
#   control data (name, version, architecture, dependencies), the exact file list, owners and modes,
#   conffiles, the binaries (architecture, stripped, hardened, large-file support on 32-bit), the maintainer scripts (run against stubbed
#   system commands: they create the user and its groups and enable/start nothing), the udev rule and the
#   unit agreeing with the scripts (user, groups, ExecStart, config path), `systemd-analyze verify` of the
#   packaged units, lintian (no error or warning; every override used), the /etc/slambooster files the packaged
#   daemon config names (power.config) being in the package, and, when the package's binaries can run here
#   (natively or through plain qemu-arm), the packaged daemon accepting the packaged config.
#
#   tests/packaging/check_deb.sh path/to/slambooster_<version>_<arch>.deb
#
# Prints one line per failed check and a summary; exits 1 when any check failed.
set -uo pipefail

deb=${1:?usage: check_deb.sh slambooster_VERSION_ARCH.deb}
root=$(cd "$(dirname "$0")/../.." && pwd)
[ -f "$deb" ] || { echo "check_deb: no such file: $deb" >&2; exit 1; }
for tool in dpkg-deb readelf lintian systemd-analyze; do
  command -v "$tool" >/dev/null || { echo "check_deb: $tool is missing (cross-toolchain/prepare_host.sh installs it)" >&2; exit 1; }
done

failures=0
checks=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
check() { checks=$((checks + 1)); }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dpkg-deb -x "$deb" "$work/root"
dpkg-deb -e "$deb" "$work/control"
field() { dpkg-deb -f "$deb" "$1"; }

# --- control data ----------------------------------------------------------------------------------------
version=$(sed -n 's/^project(slambooster VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
arch=$(field Architecture)
check; [ "$(field Package)" = slambooster ] || fail "Package is '$(field Package)', expected slambooster"
check; [ "$(field Version)" = "$version" ] || fail "Version is '$(field Version)', CMakeLists.txt says $version"
check; [ "$(basename "$deb")" = "slambooster_${version}_${arch}.deb" ] ||
  fail "file name $(basename "$deb") is not slambooster_${version}_${arch}.deb"
check; [ -n "$(field Maintainer)" ] || fail "no Maintainer"
depends=$(field Depends)
dep_names=$(sed 's/([^)]*)//g; s/ //g' <<<"$depends" | tr ',|' '\n\n')
for dep in adduser init-system-helpers libc6 libstdc++6 libpng16-16 libsystemd0; do
  check; grep -qxF "$dep" <<<"$dep_names" || fail "Depends lacks $dep: $depends"
done

# --- files, owners, modes --------------------------------------------------------------------------------
expected_files="./etc/slambooster/pipeline.json
./etc/slambooster/power.json
./etc/slambooster/slamboosterd.json
./lib/systemd/system/slambooster.service
./lib/systemd/system/slambooster.socket
./lib/udev/rules.d/60-slambooster.rules
./usr/bin/slambooster
./usr/bin/slamboosterctl
./usr/sbin/slamboosterd
./usr/share/doc/slambooster/changelog.gz
./usr/share/doc/slambooster/copyright
./usr/share/lintian/overrides/slambooster
./usr/share/man/man1/slambooster.1.gz
./usr/share/man/man1/slamboosterctl.1.gz
./usr/share/man/man8/slamboosterd.8.gz"
listing=$(dpkg-deb -c "$deb")
actual_files=$(awk '$1 !~ /^d/ {print $6}' <<<"$listing" | sort)
check; if [ "$actual_files" != "$expected_files" ]; then
  fail "file list differs (< expected, > packaged):"
  diff <(echo "$expected_files") <(echo "$actual_files") | grep '^[<>]' | sed 's/^/      /'
fi
while read -r mode owner _ _ _ path _; do
  check; [ "$owner" = root/root ] || fail "$path is owned by $owner, expected root/root"
  case "$mode:$path" in
    d*) want=drwxr-xr-x ;;
    *:./usr/bin/*|*:./usr/sbin/*) want=-rwxr-xr-x ;;
    *) want=-rw-r--r-- ;;
  esac
  check; [ "$mode" = "$want" ] || fail "$path has mode $mode, expected $want"
done <<<"$listing"

# --- conffiles and maintainer scripts --------------------------------------------------------------------
check; [ "$(sort "$work/control/conffiles")" = "$(grep '^./etc/' <<<"$expected_files" | sed 's/^\.//')" ] ||
  fail "conffiles are '$(tr '\n' ' ' <"$work/control/conffiles")', expected every file under /etc"
for script in postinst prerm postrm; do
  check; [ -f "$work/control/$script" ] || { fail "no $script"; continue; }
  check; [ "$(stat -c %a "$work/control/$script")" = 755 ] || fail "$script mode $(stat -c %a "$work/control/$script")"
  check; sh -n "$work/control/$script" || fail "$script: shell syntax error"
done

# Run the scripts against stubs of the system commands they use; each stub logs its arguments. The stubbed
# system knows groups dialout/plugdev/video; the user exists only after `adduser --system` ran.
stubs="$work/stubs"; mkdir -p "$stubs"; log="$work/calls.log"; state="$work/state"; mkdir -p "$state"
for cmd in adduser systemctl deb-systemd-invoke deb-systemd-helper udevadm rm; do
  printf '#!/bin/sh\necho "%s $*" >>"%s"\n' "$cmd" "$log" >"$stubs/$cmd"
done
cat >>"$stubs/adduser" <<EOF
case "\$*" in *--system*) touch "$state/user" ;; *) touch "$state/group-\$(echo "\$*" | awk '{print \$NF}')" ;; esac
EOF
cat >"$stubs/getent" <<EOF
#!/bin/sh
case "\$1 \$2" in
  "passwd slambooster") [ -e "$state/user" ] ;;
  "group dialout"|"group plugdev"|"group video") exit 0 ;;
  *) exit 2 ;;
esac
EOF
cat >"$stubs/id" <<EOF
#!/bin/sh
groups=slambooster; for g in dialout plugdev video; do [ -e "$state/group-\$g" ] && groups="\$groups \$g"; done
echo "\$groups"
EOF
chmod +x "$stubs"/*
run_script() { # script args... -> $calls: the stubbed commands it ran, in order
  : >"$log"
  check; PATH="$stubs:$PATH" sh "$work/control/$1" "${@:2}" || fail "$* exited $?"
  calls=$(cat "$log")
}

run_script postinst configure ""
check; grep -q '^adduser --system .*--group.* slambooster$' <<<"$calls" || fail "fresh install: no 'adduser --system --group ... slambooster' ($calls)"
for g in dialout plugdev video; do
  check; grep -qx "adduser --quiet slambooster $g" <<<"$calls" || fail "fresh install: slambooster not added to $g"
done
check; ! grep -Eq 'enable|(^| )start( |$)|restart' <<<"$calls" || fail "fresh install enables or starts something: $calls"
run_script postinst configure 0.0.9
check; [ -z "$(grep adduser <<<"$calls")" ] || fail "upgrade with the user in place re-ran adduser: $calls"
check; ! grep -Eq 'enable|(^| )start( |$)' <<<"$calls" || fail "upgrade enables or starts something: $calls"
# Whether systemd runs decides the daemon-reload / try-restart branch; check what the scripts say they do.
check; grep -q 'deb-systemd-invoke try-restart slambooster.service' "$work/control/postinst" ||
  fail "postinst does not restart a running service on upgrade"
check; ! grep -v '^ *#' "$work/control/postinst" |
  grep -Eq 'systemctl (--system )?(enable|start)|deb-systemd-helper enable|deb-systemd-invoke (start|restart)' ||
  fail "postinst enables or starts the service"
run_script postrm purge
check; grep -qx 'rm -rf /var/lib/slambooster' <<<"$calls" || fail "purge does not remove /var/lib/slambooster: $calls"
run_script postrm remove
check; ! grep -q '^rm ' <<<"$calls" || fail "remove (not purge) deletes data: $calls"
check; grep -q 'deb-systemd-invoke stop slambooster.service' "$work/control/prerm" || fail "prerm does not stop the service"

# --- the dpkg life cycle in a sandbox root: install, upgrade keeping an edited config, remove, purge ----------
# dpkg --root with chrootless scripts (they see DPKG_ROOT and act inside it); the system commands are the stubs
# above. Dependencies and the architecture are forced: the sandbox holds no other package.
sandbox="$work/sandbox"
mkdir -p "$sandbox/var/lib/dpkg/updates" "$sandbox/var/lib/dpkg/info"
touch "$sandbox/var/lib/dpkg/status" "$sandbox/var/lib/dpkg/available"
sb_stubs="$work/sandbox-stubs"  # the stubs; rm deletes inside the sandbox only (a script ignoring DPKG_ROOT fails)
mkdir -p "$sb_stubs"; cp -p "$stubs"/* "$sb_stubs"/
cat >"$sb_stubs/rm" <<EOF
#!/bin/sh
for a in "\$@"; do
  case "\$a" in -*|"$sandbox"/*) ;; *) echo "check_deb: refusing rm outside the sandbox: \$a" >&2; exit 1 ;; esac
done
exec /bin/rm "\$@"
EOF
sb_dpkg() { PATH="$sb_stubs:$PATH" dpkg --root="$sandbox" --force-script-chrootless --force-not-root \
  --force-depends --force-architecture --force-confold "$@" >>"$work/dpkg.log" 2>&1; }
repack() { # new_version edit_default_config -> $work/next.deb: this package as another version
  rm -rf "$work/repack"; dpkg-deb -R "$deb" "$work/repack"
  sed -i "s/^Version: .*/Version: $1/" "$work/repack/DEBIAN/control"
  if [ "$2" = yes ]; then
    sed -i 's/"log_level": "info"/"log_level": "warn"/' "$work/repack/etc/slambooster/slamboosterd.json"
  fi
  dpkg-deb --root-owner-group -b "$work/repack" "$work/next.deb" >/dev/null
}
conf="$sandbox/etc/slambooster/slamboosterd.json"
status_of() { dpkg-query --admindir="$sandbox/var/lib/dpkg" -W -f='${db:Status-Status} ${Version}' slambooster 2>/dev/null; }
rm -f "$state"/*
check; sb_dpkg -i "$deb" || fail "dpkg -i into a sandbox failed: $(tail -5 "$work/dpkg.log")"
check; [ "$(status_of)" = "installed $version" ] || fail "after install: status '$(status_of)'"
check; [ -x "$sandbox/usr/sbin/slamboosterd" ] && [ -f "$conf" ] || fail "after install: files missing"
echo '{"edited": "by the user"}' >"$conf"
edited=$(cat "$conf")
repack "$version.1" no
check; sb_dpkg -i "$work/next.deb" || fail "upgrade failed: $(tail -5 "$work/dpkg.log")"
check; [ "$(cat "$conf")" = "$edited" ] || fail "upgrade (same default config) replaced the user's edited config"
check; [ ! -e "$conf.dpkg-dist" ] || fail "upgrade with an unchanged default wrote $conf.dpkg-dist"
repack "$version.2" yes
check; sb_dpkg -i "$work/next.deb" || fail "upgrade failed: $(tail -5 "$work/dpkg.log")"
check; [ "$(cat "$conf")" = "$edited" ] || fail "upgrade (new default config) replaced the user's edited config"
check; grep -q '"log_level": "warn"' "$conf.dpkg-dist" 2>/dev/null ||
  fail "upgrade with a new default did not leave it beside the edited one as $conf.dpkg-dist"
mkdir -p "$sandbox/var/lib/slambooster/run1" && touch "$sandbox/var/lib/slambooster/run1/trajectory.tum"
check; sb_dpkg -r slambooster || fail "remove failed: $(tail -5 "$work/dpkg.log")"
check; [ ! -e "$sandbox/usr/sbin/slamboosterd" ] && [ -f "$conf" ] ||
  fail "remove: binaries should be gone and the config kept"
check; [ -e "$sandbox/var/lib/slambooster/run1/trajectory.tum" ] || fail "remove (not purge) deleted run outputs"
check; sb_dpkg -P slambooster || fail "purge failed: $(tail -5 "$work/dpkg.log")"
check; [ ! -e "$sandbox/etc/slambooster" ] && [ ! -e "$sandbox/var/lib/slambooster" ] ||
  fail "purge left $(ls -d "$sandbox/etc/slambooster" "$sandbox/var/lib/slambooster" 2>/dev/null)"

# --- binaries --------------------------------------------------------------------------------------------
case "$arch" in
  armhf) machine=ARM ;;
  amd64) machine="Advanced Micro Devices X86-64" ;;
  *) machine="" ;;
esac
for bin in usr/bin/slambooster usr/bin/slamboosterctl usr/sbin/slamboosterd; do
  f="$work/root/$bin"
  check; [ -z "$machine" ] || readelf -h "$f" | grep -q "Machine: *$machine\$" ||
    fail "$bin is not a $arch binary: $(readelf -h "$f" | grep Machine)"
  if [ "$arch" = armhf ]; then
    check; readelf -h "$f" | grep -q 'hard-float ABI' || fail "$bin is not hard-float"
  fi
  check; ! readelf -S "$f" | grep -q '\.symtab' || fail "$bin is not stripped"
  check; readelf -d "$f" | grep -q 'BIND_NOW' || fail "$bin lacks BIND_NOW (full RELRO)"
  # Large-file support (32-bit targets): outputs of a weeks-long session pass 2 GiB.
  check; lfs_out=$(bash "$root/tests/packaging/check_lfs.sh" "$f") || fail "$bin: $(grep FAIL <<<"$lfs_out")"
  # 64-bit time (32-bit targets): file times and clock stamps past 2038, and no library call whose time_t or
  # timeval is 32 bits on the library's side.
  check; time_out=$(bash "$root/tests/packaging/check_time64.sh" "$f") || fail "$bin: $(grep FAIL <<<"$time_out")"
done

# --- unit, udev rule and scripts agree --------------------------------------------------------------------
unit="$work/root/lib/systemd/system/slambooster.service"
exec_bin=$(sed -n 's/^ExecStart=\([^ ]*\).*/\1/p' "$unit")
check; [ -x "$work/root$exec_bin" ] || fail "ExecStart=$exec_bin is not in the package"
config=$(sed -n 's/^ExecStart=.*--config \([^ ]*\).*/\1/p' "$unit")
check; [ -f "$work/root$config" ] || fail "the unit's --config '$config' is not in the package"
check; [ "$(sed -n 's/^User=//p' "$unit")" = slambooster ] || fail "unit User= is not slambooster"
check; [ "$(sed -n 's/^SupplementaryGroups=//p' "$unit" | tr ' ' '\n' | sort | tr '\n' ' ')" = "dialout plugdev video " ] ||
  fail "unit SupplementaryGroups= is not dialout plugdev video"
check; ! grep -q '^DynamicUser=yes' "$unit" || fail "unit uses DynamicUser= although the package creates a user"
rules="$work/root/lib/udev/rules.d/60-slambooster.rules"
rule_for() { grep -v '^#' "$rules" | grep "$1" | grep "$2"; }
check; rule_for '"10c4"' '"ea60"' | grep -q 'GROUP="dialout"' || fail "udev: CP210x (SmartPower2/3) not given to dialout"
check; rule_for '"04d8"' '"003f"' | grep -q 'GROUP="plugdev"' || fail "udev: SmartPower v1 HID not given to plugdev"
check; rule_for '"1d27"' 'usb_device' | grep -q 'GROUP="video"' || fail "udev: PrimeSense cameras not given to video"
check; rule_for '"045e"' '02ae' | grep -q 'GROUP="video"' || fail "udev: Kinect camera not given to video"
check; ! grep -v '^#' "$rules" | grep -q 'MODE="06[0-9]6"' || fail "udev: a rule makes a device world-writable"
while IFS= read -r line; do  # every rule line: comma-separated KEY op "value" pairs
  [ -z "$line" ] || [ "${line#\#}" != "$line" ] && continue
  check; grep -Eq '^([A-Z]+(\{[A-Za-z_]+\})? *(==|!=|=|\+=|:=) *"[^"]*"(, *|$))+$' <<<"$line" ||
    fail "udev: malformed rule: $line"
done <"$rules"

# --- systemd-analyze verify (the package's root plus the host's targets and /bin/kill that units refer to) -
vroot="$work/verify-root"
cp -a "$work/root" "$vroot"
mkdir -p "$vroot/bin"
cp /bin/kill "$vroot/bin/kill"
for u in /lib/systemd/system/*.target /lib/systemd/system/*.slice /lib/systemd/system/*.mount; do
  [ -e "$vroot/lib/systemd/system/$(basename "$u")" ] || cp -P "$u" "$vroot/lib/systemd/system/"
done
verify_out=$(systemd-analyze verify --man=no --root="$vroot" \
  /lib/systemd/system/slambooster.service /lib/systemd/system/slambooster.socket 2>&1)
verify_rc=$?
check; [ $verify_rc -eq 0 ] && [ -z "$verify_out" ] || fail "systemd-analyze verify (exit $verify_rc): $verify_out"

# --- lintian ---------------------------------------------------------------------------------------------
# -I shows info tags too, among them unused-override (an override whose tag no longer fires).
lintian_out=$(lintian --fail-on error,warning -I "$deb" 2>&1 | grep -v 'running with root privileges')
lintian_rc=${PIPESTATUS[0]}
check; [ "$lintian_rc" -eq 0 ] || fail "lintian (exit $lintian_rc): $(grep -E '^[EW]:' <<<"$lintian_out")"
# lintian reports a binary without large-file support as information only (I:); here it fails.
check; ! grep -q 'binary-file-built-without-LFS-support' <<<"$lintian_out" ||
  fail "lintian: $(grep 'binary-file-built-without-LFS-support' <<<"$lintian_out")"
check; ! grep -Eq 'unused-override|mismatched-override' <<<"$lintian_out" ||
  fail "lintian overrides that no longer apply: $(grep -E 'unused-override|mismatched-override' <<<"$lintian_out")"

# --- files the packaged config names (power.config = /etc/slambooster/power.json) are in the package -------
daemon_conf="$work/root/etc/slambooster/slamboosterd.json"
for named in $(grep -o '"/etc/slambooster/[^"]*"' "$daemon_conf" | tr -d '"' | sort -u); do
  check; [ -f "$work/root$named" ] || fail "slamboosterd.json names $named, which the package does not ship"
done

# --- the packaged daemon accepts the packaged config (runs the armhf binary through plain qemu-arm) --------
runner=()
if [ "$arch" = armhf ] && command -v qemu-arm >/dev/null; then
  runner=(qemu-arm)
elif [ "$arch" = "$(dpkg --print-architecture)" ]; then
  runner=(env)
fi
if [ ${#runner[@]} -gt 0 ]; then
  out=$("${runner[@]}" "$work/root/usr/sbin/slamboosterd" --check-config --config "$work/root/etc/slambooster/slamboosterd.json" 2>&1)
  rc=$?
  check; [ $rc -eq 0 ] || fail "packaged slamboosterd rejects the packaged config (exit $rc): $out"
  out=$("${runner[@]}" "$work/root/usr/bin/slambooster" --version 2>&1)
  check; grep -q "$version" <<<"$out" || fail "packaged slambooster --version says '$out', expected $version"
else
  echo "check_deb: note: $arch binaries cannot run here (no qemu-arm); the config check was not run"
  fail "cannot run the packaged binaries to check the packaged config"
fi

echo "check_deb: $(basename "$deb"): $checks checks, $failures failed"
[ "$failures" -eq 0 ]
