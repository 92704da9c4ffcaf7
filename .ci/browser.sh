#!/usr/bin/env bash
# Issue 5: Debian's Chromium (and fonts) for tests/test_browser.py, which Playwright drives headless.
# Playwright's own browser download does not work here: never `playwright install`.
# CI runs this as root before the test suites; it installs only what is missing.
set -euo pipefail

missing=()
[ -x /usr/bin/chromium ] || missing+=(chromium)
dpkg -s fonts-liberation >/dev/null 2>&1 || missing+=(fonts-liberation)
if [ ${#missing[@]} -eq 0 ]; then
    echo "browser: $(/usr/bin/chromium --version 2>/dev/null || echo chromium) already installed"
    exit 0
fi
bash "$(dirname "$0")/apt-install.sh" browser "${missing[@]}"
echo "browser: $(/usr/bin/chromium --version)"
