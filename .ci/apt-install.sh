#!/usr/bin/env bash
# apt-install.sh LABEL PACKAGE...: install Debian packages for a CI step (as root; the caller checked they are missing).
set -euo pipefail
label=$1
shift
if [ "$(id -u)" != 0 ]; then
    echo "$label: $* missing and not root: run as root: apt-get install -y $*" >&2
    exit 1
fi
echo "$label: apt-get install $*"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >/dev/null
apt-get install -y -q "$@" >/dev/null
