#!/usr/bin/env bash
# Runs the full paper-scale study (data/studies/paper-scale.json, 430,080 points) on a build
# pinned to one commit, resumably, and keeps what is done safe across a machine that does not
# survive the session.
#
#   bash tools/dev/full_study.sh run COMMIT     # build COMMIT in a worktree (once), run or resume
#   bash tools/dev/full_study.sh checkpoint     # store results.csv (+ sidecar, log) in git
#   bash tools/dev/full_study.sh restore        # bring the stored checkpoint back to resume
#   bash tools/dev/full_study.sh report         # each index once? wall time; Tables 2-3
#
# Work folder: $GAPCHAIN_STUDY_DIR (default /work/runs/paper-scale). `run` appends "segment
# start/end" lines and a 30 s heartbeat (rows on disk) to segments.log: the study's wall time is
# the sum of its segments. The checkpoint is a commit on the branch runs/paper-scale (plumbing
# only: the working tree and main are not touched), so it lives as long as the repository does.
set -euo pipefail
repo=$(git -C "$(dirname "$0")" rev-parse --show-toplevel)
dir=${GAPCHAIN_STUDY_DIR:-/work/runs/paper-scale}
branch=runs/paper-scale
mkdir -p "$dir"

build_pinned() {
    local commit=$1 tree="$dir/src"
    if [ ! -x "$tree/build/bin/gapchain-sweep" ] || [ "$(git -C "$tree" rev-parse HEAD)" != "$(git -C "$repo" rev-parse "$commit")" ]; then
        rm -rf "$tree"
        git -C "$repo" worktree prune
        git -C "$repo" worktree add --detach "$tree" "$commit" >/dev/null
        cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
        cmake --build "$tree/build" -j2 --target gapchain-sweep >/dev/null
    fi
    git -C "$tree" rev-parse HEAD > "$dir/commit"
}

case ${1:-} in
run)
    [ $# -eq 2 ] || { echo "usage: $0 run COMMIT" >&2; exit 2; }
    build_pinned "$2"
    cd "$dir"
    echo "segment start $(date -u +%FT%TZ) commit $(cat commit)" >> segments.log
    (while sleep 30; do
        echo "heartbeat $(date -u +%FT%TZ) rows $(($(wc -l < results.csv 2>/dev/null || echo 1) - 1))" >> segments.log
    done) &
    beat=$!
    trap 'kill $beat 2>/dev/null; echo "segment end $(date -u +%FT%TZ)" >> segments.log' EXIT
    "$dir/src/build/bin/gapchain-sweep" "$repo/data/studies/paper-scale.json" \
        --out results.csv --threads 2 2>> sweep.log
    ;;
checkpoint)
    cd "$dir"
    files=(results.csv results.csv.json segments.log commit)
    entries=""
    for f in "${files[@]}"; do
        [ -f "$f" ] || continue
        # A snapshot first: the sweep may be appending (a torn last row is dropped on resume).
        cp "$f" "$f.snapshot"
        [ "$f" = results.csv ] && rows=$(($(wc -l < "$f.snapshot") - 1))
        blob=$(gzip -c "$f.snapshot" | git -C "$repo" hash-object -w --stdin)
        rm -f "$f.snapshot"
        entries+=$(printf '100644 blob %s\t%s.gz' "$blob" "$f")$'\n'
    done
    tree=$(printf '%s' "$entries" | git -C "$repo" mktree)
    parent=$(git -C "$repo" rev-parse -q --verify "refs/heads/$branch" || true)
    commit=$(git -C "$repo" commit-tree "$tree" ${parent:+-p "$parent"} \
        -m "paper-scale study checkpoint: ${rows:-0} rows (a torn last one included), $(date -u +%FT%TZ)")
    git -C "$repo" update-ref "refs/heads/$branch" "$commit"
    echo "checkpoint $commit on $branch"
    ;;
restore)
    cd "$dir"
    for f in results.csv results.csv.json segments.log commit; do
        git -C "$repo" cat-file -e "$branch:$f.gz" 2>/dev/null || continue
        git -C "$repo" cat-file blob "$branch:$f.gz" | gunzip > "$f"
    done
    echo "restored $(($(wc -l < results.csv) - 1)) rows of commit $(cat commit) into $dir"
    ;;
report)
    cd "$dir"
    echo "commit $(cat commit)"
    # Each index once, and the wall time as the sum of the segments (start to end, or to the
    # last heartbeat of a segment the machine took down).
    python3 - <<'PY'
import csv, datetime
rows = list(csv.DictReader(open("results.csv")))
idx = [int(r["index"]) for r in rows]
print(f"rows {len(rows)}, distinct indices {len(set(idx))}, range {min(idx)}..{max(idx)}, "
      f"every index of 0..430079 exactly once: {sorted(idx) == list(range(430080))}")
t = lambda s: datetime.datetime.fromisoformat(s.replace("Z", "+00:00"))
total, start, last = 0.0, None, None
for line in open("segments.log"):
    w = line.split()
    if w[:2] == ["segment", "start"]:
        if start and last: total += (last - start).total_seconds()
        start, last = t(w[2]), t(w[2])
    elif w[:2] == ["segment", "end"] or w[0] == "heartbeat":
        last = t(w[-1] if w[0] == "segment" else w[1])
if start and last: total += (last - start).total_seconds()
print(f"wall time, sum of segments: {total:.0f} s = {total / 3600:.2f} h")
PY
    python3 "$repo/docs/plot/study_time.py" results.csv
    python3 "$repo/docs/plot/tables_2_3.py" results.csv
    ;;
*)
    sed -n "2,/^set -euo/p" "$0" | sed "$ d" >&2
    exit 2
    ;;
esac
