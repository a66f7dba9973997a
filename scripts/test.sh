#!/usr/bin/env bash
# Installs what is missing, builds (scripts/setup.sh) and runs the whole test suite.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
status=0
ctest --test-dir build --output-on-failure -j2 || status=$?
exit "$status"
