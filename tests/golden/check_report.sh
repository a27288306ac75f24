#!/usr/bin/env bash
# Runs check_report.py (report.json against docs/report-schema.json) with a python3 that has the
# jsonschema module: Debian's /usr/bin/python3 (python3-jsonschema, tools/debian-packages.txt)
# first, else the python3 on PATH. Fails when neither has it: the check is never skipped.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for python in /usr/bin/python3 python3; do
  if command -v "$python" >/dev/null && "$python" -c 'import jsonschema' 2>/dev/null; then
    exec "$python" "$here/check_report.py" "$@"
  fi
done
echo "check_report: no python3 with the jsonschema module (apt-get install python3-jsonschema)"
exit 1
