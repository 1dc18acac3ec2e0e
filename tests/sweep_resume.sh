#!/usr/bin/env bash
# A sweep killed with kill -9 and run again ends with the same rows as an uninterrupted one;
# so do 1 and 2 threads and two shards. Usage: sweep_resume.sh GAPCHAIN_SWEEP STUDY
set -u
sweep=$1
study=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
rows() { tail -n +2 "$1" | sort; }

"$sweep" "$study" --threads 2 --out "$dir/full.csv" >/dev/null 2>&1 || { echo "FAIL: uninterrupted run"; exit 1; }
total=$(($(wc -l < "$dir/full.csv") - 1))
echo "uninterrupted: $total rows"

"$sweep" "$study" --threads 2 --out "$dir/killed.csv" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 400); do
    [ -f "$dir/killed.csv" ] && [ "$(wc -l < "$dir/killed.csv")" -gt 10 ] && break
    sleep 0.02
done
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
partial=$(($(wc -l < "$dir/killed.csv") - 1))
echo "killed after $partial rows"
if [ "$partial" -ge "$total" ]; then echo "FAIL: the run finished before the kill"; fail=1; fi
"$sweep" "$study" --threads 2 --out "$dir/killed.csv" >/dev/null 2>&1 || { echo "FAIL: resumed run"; fail=1; }
if ! diff <(rows "$dir/full.csv") <(rows "$dir/killed.csv") >/dev/null; then
    echo "FAIL: killed + resumed rows differ from the uninterrupted run"; fail=1
fi
if [ "$(cut -d, -f1 "$dir/killed.csv" | sort | uniq -d | wc -l)" -ne 0 ]; then
    echo "FAIL: a point was done twice"; fail=1
fi

"$sweep" "$study" --threads 1 --out "$dir/one.csv" >/dev/null 2>&1
diff <(rows "$dir/full.csv") <(rows "$dir/one.csv") >/dev/null || { echo "FAIL: 1 thread differs from 2"; fail=1; }

"$sweep" "$study" --shard 0/2 --out "$dir/shards.csv" >/dev/null 2>&1
"$sweep" "$study" --shard 1/2 --out "$dir/shards.csv" >/dev/null 2>&1
diff <(rows "$dir/full.csv") <(rows "$dir/shards.csv") >/dev/null || { echo "FAIL: two shards differ"; fail=1; }

# A second sweep on a file another one is writing is refused (the file is locked).
"$sweep" "$study" --out "$dir/locked.csv" >/dev/null 2>&1 &
first=$!
for _ in $(seq 1 400); do [ -s "$dir/locked.csv" ] && break; sleep 0.02; done
"$sweep" "$study" --out "$dir/locked.csv" >/dev/null 2>"$dir/locked.err"
rc=$?
kill -9 "$first" 2>/dev/null; wait "$first" 2>/dev/null
if [ "$rc" -ne 2 ] || ! grep -q "another gapchain-sweep" "$dir/locked.err"; then
    echo "FAIL: a second sweep on a busy file was not refused"; fail=1
fi

# A torn last row (a kill in the middle of a write) is dropped and redone.
head -c -7 "$dir/full.csv" > "$dir/torn.csv"
cp "$dir/full.csv.json" "$dir/torn.csv.json"
"$sweep" "$study" --out "$dir/torn.csv" >/dev/null 2>&1
diff <(rows "$dir/full.csv") <(rows "$dir/torn.csv") >/dev/null || { echo "FAIL: torn row not redone"; fail=1; }

# A row twice (an edited or merged file) or a damaged row is refused, the file untouched.
{ cat "$dir/full.csv"; tail -n 1 "$dir/full.csv"; } > "$dir/twice.csv"
cp "$dir/full.csv.json" "$dir/twice.csv.json"
cp "$dir/twice.csv" "$dir/twice.before"
if "$sweep" "$study" --out "$dir/twice.csv" >/dev/null 2>"$dir/twice.err" ||
    ! grep -q "has two rows" "$dir/twice.err" || ! cmp -s "$dir/twice.csv" "$dir/twice.before"; then
    echo "FAIL: a duplicated row was not refused"; fail=1
fi
sed '2s/^\([0-9]*\),[^,]*,/\1,abc,/' "$dir/full.csv" > "$dir/edited.csv"
cp "$dir/full.csv.json" "$dir/edited.csv.json"
if "$sweep" "$study" --out "$dir/edited.csv" >/dev/null 2>"$dir/edited.err" ||
    ! grep -q "unreadable row" "$dir/edited.err"; then
    echo "FAIL: a damaged row was not refused"; fail=1
fi

# A fresh start writes its own sidecar: one left without its CSV (or another file of that name)
# was kept, and then described another study.
echo '{"mine": 1}' > "$dir/orphan.csv.json"
"$sweep" "$study" --out "$dir/orphan.csv" >/dev/null 2>&1
if ! cmp -s <(grep -v '"study"' "$dir/full.csv.json") <(grep -v '"study"' "$dir/orphan.csv.json"); then
    echo "FAIL: a sidecar without its CSV was kept"; fail=1
fi
# ... and puts back what was there if it cannot start.
echo '{"mine": 1}' > "$dir/blocked.csv.json"
mkdir "$dir/blocked.csv"
"$sweep" "$study" --out "$dir/blocked.csv" >/dev/null 2>&1
if [ "$(cat "$dir/blocked.csv.json")" != '{"mine": 1}' ]; then
    echo "FAIL: a refused fresh start did not put the old sidecar back"; fail=1
fi

[ "$fail" -eq 0 ] && echo "sweep resume, threads, shards and torn-row checks passed"
exit $fail
