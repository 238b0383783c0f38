#!/usr/bin/env bash
# How long a newcomer waits for the first picture on a fresh Debian 12 machine: makes a minimal
# Debian 12 root (debootstrap, minbase: less than a cloud image has), clones this repository's
# HEAD into it and runs the README's main command there (scripts/run-main.sh), which prints the
# seconds to its picture: install, build, main job. Needs root and the network to Debian's
# archive; takes the fresh root's directory as its argument (default /tmp/vimpact-fresh, made
# anew).
#
#   sudo bash scripts/first-picture.sh [DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
root=${1:-/tmp/vimpact-fresh}
[ "$(id -u)" = 0 ] || { echo "first-picture: needs root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap > /dev/null || apt-get install -y debootstrap > /dev/null
# Only a root this script made is removed (its mark file), never another directory.
if [ -e "$root" ] && [ ! -f "$root/.vimpact-fresh-root" ]; then
  echo "first-picture: $root exists and was not made by this script; name a new directory" >&2
  exit 2
fi
if mountpoint -q "$root/proc" 2> /dev/null; then umount "$root/proc"; fi
rm -rf "$root"
mkdir -p "$root" && touch "$root/.vimpact-fresh-root"
debootstrap --variant=minbase bookworm "$root" http://deb.debian.org/debian > "$root.log" 2>&1 ||
  { tail -20 "$root.log"; exit 1; }
cp /etc/resolv.conf "$root/etc/"
git clone -q "$PWD" "$root/root/vimpact"
mount -t proc proc "$root/proc"
trap 'umount "$root/proc"' EXIT
echo "first-picture: $(nproc) cores; the README's main command in a fresh Debian 12 root ($root)"
chroot "$root" /bin/bash -c 'cd /root/vimpact && bash scripts/run-main.sh' | grep -E "first picture|main job done"
