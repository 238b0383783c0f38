#!/usr/bin/env bash
# Every figure script in turn: examples/all.sh [--quick]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
for f in "$here"/fig*.sh; do
  echo "== $(basename "$f")"
  bash "$f" "$@"
done
