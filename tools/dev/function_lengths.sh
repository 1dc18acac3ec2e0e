#!/usr/bin/env bash
# Lists the functions of lib/ and tools/ longer than a limit (default 60 lines, counted from the
# line of the name to the closing brace), as Universal Ctags sees them. Exit 1 if any.
# Usage: bash tools/dev/function_lengths.sh [LIMIT]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
limit=${1:-60}
cd "$root"
ctags -R --languages=C++ --c++-kinds=f --fields=+ne -o - lib tools |
    awk -F'\t' -v limit="$limit" '
        { line = 0; end = 0
          for (i = 4; i <= NF; i++) {
              if ($i ~ /^line:/) line = substr($i, 6)
              if ($i ~ /^end:/) end = substr($i, 5)
          }
          if (line && end && end - line + 1 > limit) {
              printf "%s:%d %s %d lines\n", $2, line, $1, end - line + 1; n++ }
        }
        END { if (n) exit 1; print "no function over " limit " lines" }'
