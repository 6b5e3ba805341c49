#!/bin/bash
# The whole test suite, three levels (core+app pytest, freecadcmd -t TestProgSurfApp, GUI under
# Xvfb); installs what it needs first. The last line reads "N passed, N failed, N skipped".
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
./install.sh
exec .venv/bin/python tests/run_suite.py "$@"
