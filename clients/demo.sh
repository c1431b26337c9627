#!/usr/bin/env bash
# `make run`: start granulabd on an SQLite file, submit the two-cube demo (Fig. 5c), wait for it, fetch its
# results, and leave the daemon serving in the foreground (Ctrl-C stops it; jobs survive in the file).
set -euo pipefail
build=${BUILD:-build}
port=${PORT:-8080}
db=${DB:-var/granulab.db}
export GRANULAB_SERVER=http://127.0.0.1:$port

mkdir -p "$(dirname "$db")"
"$build/granulabd" --port "$port" --db "$db" &
daemon=$!
# Stops the daemon once. A command that fails inside a trap would end the script with its status under set -e
# (the daemon already gone, say, after the terminal's Ctrl-C reached it too): nothing here may fail.
stop() {
  trap - EXIT
  if kill -TERM "$daemon" 2>/dev/null; then wait "$daemon" 2>/dev/null || true; fi
}
# Ctrl-C (or a TERM) is how this is meant to end: stop the daemon and exit 0, so make reports no error.
trap 'stop; echo "granulabd stopped (the jobs are kept in $db)"; exit 0' INT TERM
trap stop EXIT
for _ in $(seq 100); do "$build/granulab" list >/dev/null 2>&1 && break; sleep 0.1; done

echo "== submitting examples/two_cube_f03.json (two sliding cubes, f = 0.3; Fig. 5c of the paper)"
id=$("$build/granulab" submit examples/two_cube_f03.json --reuse)   # prints the job id
echo "job $id"
"$build/granulab" wait "$id"
"$build/granulab" results "$id" --out out/demo
echo "== first rows of out/demo/curve.csv (u/l, P/P0, T/P0, P, T):"
head -5 out/demo/curve.csv
echo "== granulabd keeps serving at $GRANULAB_SERVER (database $db). Open $GRANULAB_SERVER/ in a browser; try"
echo "   build/granulab submit examples/crystal_quick.json          (a small crystal, about 15 s)"
echo "   build/granulab submit examples/fig7c_p30.json --dry-run    (the paper's size: its cost first; the dry run says how long here)"
echo "   (Ctrl-C stops the daemon)"
wait $daemon
