#!/usr/bin/env bash
# Issue 18 (play it yourself): tmux for tests/test_play_terminal.py, which plays the keyboard game in a
# shell with job control (Ctrl-Z, fg). CI runs this as root before the test suites; it installs only what is missing.
set -euo pipefail

if command -v tmux >/dev/null 2>&1; then
    echo "play: $(tmux -V) already installed"
    exit 0
fi
bash "$(dirname "$0")/apt-install.sh" play tmux
echo "play: $(tmux -V)"
