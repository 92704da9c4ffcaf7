#!/usr/bin/env bash
# Issue 19: the documentation site. A fresh venv with the docs extra, `mkdocs build --strict`
# (a broken link or reference, or a notebook that fails to execute, fails the build), then the
# built site in headless Chromium (tests_docs/; Chromium from .ci/browser.sh). No torch needed.
set -euo pipefail
cd "$(dirname "$0")/.."

# DOCS_VENV=DIR: add the docs extra to that venv instead of making a fresh one (.ci/run passes the
# notebook stage's venv, which already holds the notebook extra the docs extra includes)
venv=${DOCS_VENV:-.venv-docs-ci}
rm -rf site
if [ -z "${DOCS_VENV:-}" ]; then
    .ci/venv "$venv"
fi
.ci/locked "$venv/bin/pip" install -q -e ".[docs]" pytest playwright
"$venv/bin/pip" check

# MkDocs 1.x and its plugins print a notice about MkDocs 2 on every build; it is not about this site
export NO_MKDOCS_2_WARNING=1 DISABLE_MKDOCS_2_WARNING=true
start=$(date +%s)
"$venv/bin/mkdocs" build --strict
echo "docs: site built in $(( $(date +%s) - start )) s"
"$venv/bin/python" -m pytest -q -p no:cacheprovider tests_docs
