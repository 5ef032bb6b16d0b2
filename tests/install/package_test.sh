#!/usr/bin/env bash
# The Debian package on a bare Debian 12 (issue 39; scripts/test --all, stage "package test"):
#   1. a root made by `debootstrap --variant=minbase bookworm` from the machine's Debian registry;
#   2. the machine's certificate authorities copied in (/usr/local/share/ca-certificates/,
#      /etc/ssl/certs/ca-certificates.crt), and its apt Acquire settings, before apt-get runs;
#   3. `apt-get install ./ocp-sim_*.deb` there: Depends resolved from the registry alone;
#   4. the installed programs' main jobs, by install_test.sh --inside /usr in the root:
#      ocp_conformance vehicle -- vehicle_client, a few campaign worlds, the installed scenario
#      library, player_sim's dashboard fetched over HTTP, missing data as exit 2.
# Everything runs in a private mount namespace, so the root's /proc and /dev go with it.
# Needs root and debootstrap (scripts/setup --all). Prints each step's time.
# Usage: package_test.sh [--root DIR] PACKAGE.deb   (OCP_DEBIAN_MIRROR overrides the registry's address)
#        package_test.sh --make-root DIR   only step 1, into DIR (made anew), for a later --root DIR:
#        scripts/test runs it beside the release tests, so the download is off CI's critical path.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage() { echo "usage: package_test.sh [--root DIR] PACKAGE.deb | --make-root DIR" >&2; exit 2; }
make_root= given_root=
case "${1:-}" in
  --make-root) [ $# -eq 2 ] || usage; make_root=$2 ;;
  --root) [ $# -eq 3 ] || usage; given_root=$2; shift 2 ;;
esac
if [ -z "$make_root" ]; then
  [ $# -eq 1 ] && [ -f "$1" ] || usage
  package=$(realpath "$1")
fi
[ "$(id -u)" -eq 0 ] || { echo "package test: needs root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap >/dev/null || { echo "package test: needs debootstrap (scripts/setup --all)" >&2; exit 2; }

# The machine's registry: the first Debian URI apt uses (deb822 or one-line sources).
registry() {   # WHAT: debian | debian-security
  { cat /etc/apt/sources.list.d/*.sources /etc/apt/sources.list 2>/dev/null || true; } |
    grep -oE "https?://[^ ]+/$1/?( |$)" | tr -d ' ' | sed 's|/$||' | head -n 1 || true
}
mirror=${OCP_DEBIAN_MIRROR:-$(registry debian)}
mirror=${mirror:-http://deb.debian.org/debian}
security=$(registry debian-security)
security=${security:-${mirror%/debian}/debian-security}

started=$(date +%s)
step() { echo "== package test: $* ($(( $(date +%s) - started )) s)"; }
# make_bare_root WORK: step 1 into WORK/root, in a private mount namespace (debootstrap mounts
# /proc and /sys in the root while it configures); WORK/ready says it finished.
make_bare_root() {
  unshare --mount --propagation private debootstrap --variant=minbase bookworm "$1/root" "$mirror" >"$1/debootstrap.log" 2>&1 ||
    { tail -n 20 "$1/debootstrap.log"; echo "package test: debootstrap failed"; return 1; }
  touch "$1/ready"
}

if [ -n "$make_root" ]; then
  rm -rf --one-file-system "$make_root" && mkdir -p "$make_root"
  make_bare_root "$make_root"
  step "debootstrap --variant=minbase bookworm from $mirror, into $make_root"
  exit 0
fi
if [ -n "$given_root" ] && [ -f "$given_root/ready" ]; then
  work=$given_root
  step "the bare root made beforehand ($work)"
else
  [ -z "$given_root" ] || echo "package test: $given_root holds no finished root; making one"
  work=$(mktemp -d /var/tmp/ocp_package_test.XXXXXX)
  trap 'rm -rf --one-file-system "$work"' EXIT
  make_bare_root "$work"
  step "debootstrap --variant=minbase bookworm from $mirror"
fi
trap 'rm -rf --one-file-system "$work"' EXIT
root=$work/root

export root mirror security package here work
unshare --mount --propagation private bash -euo pipefail -c '
step() { echo "== package test: $* ($(( $(date +%s) - $0 )) s)"; }

mkdir -p "$root/usr/local/share/ca-certificates" "$root/etc/ssl/certs"
cp -a /usr/local/share/ca-certificates/. "$root/usr/local/share/ca-certificates/" 2>/dev/null || true
[ ! -f /etc/ssl/certs/ca-certificates.crt ] || cp /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/"
cp /etc/resolv.conf "$root/etc/resolv.conf"
printf "deb %s bookworm main\ndeb %s bookworm-updates main\ndeb %s bookworm-security main\n" \
  "$mirror" "$mirror" "$security" >"$root/etc/apt/sources.list"
apt-config dump | grep -E "^Acquire::(Check-Valid-Until|Check-Date|http::Proxy|https::Proxy) " \
  >"$root/etc/apt/apt.conf.d/99from-the-machine" || true
mount -t proc proc "$root/proc"
mount --rbind /dev "$root/dev"
cp "$package" "$root/tmp/"
cp "$here/install_test.sh" "$root/tmp/install_test.sh"
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root DEBIAN_FRONTEND=noninteractive "$@"; }
in_root apt-get update -qq >"$work/apt.log" 2>&1 || { cat "$work/apt.log"; echo "package test: apt-get update failed"; exit 1; }
in_root apt-get install -y -qq --no-install-recommends "/tmp/$(basename "$package")" >>"$work/apt.log" 2>&1 ||
  { tail -n 30 "$work/apt.log"; echo "package test: apt-get install failed"; exit 1; }
step "apt-get install ./$(basename "$package") (pulled in: $(grep -c "^Setting up" "$work/apt.log") packages)"
in_root dpkg -s ocp-sim | grep -E "^(Version|Depends|Suggests):"

mkdir -p "$root/tmp/work"
in_root bash /tmp/install_test.sh --inside /usr /tmp/work
step "the installed programs in the bare root"
' "$started"
step "done, PASS"
