#!/usr/bin/env bash
# Issue 18 (play it yourself): tmux for tests/test_play_terminal.py, which plays the keyboard game in a
# shell with job control (Ctrl-Z, fg). CI runs this as root before the test suites; it installs only what is missing.
set -euo pipefail

if command -v tmux >/dev/null 2>&1; then
    echo "play: $(tmux -V) already installed"
    exit 0
fi
if [ "$(id -u)" != 0 ]; then
    echo "play: tmux missing and not root: run as root: apt-get install -y tmux" >&2
    exit 1
fi
echo "play: apt-get install tmux"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >/dev/null
apt-get install -y -q tmux >/dev/null
echo "play: $(tmux -V)"
