#!/usr/bin/env bash
# Under MPI: 1 and 2 ranks give the rows of a single-process run, and a 2-rank sweep killed with
# kill -9 (every process at once) and run again ends with the same rows.
# Usage: sweep_resume_mpi.sh MPIEXEC GAPCHAIN_SWEEP STUDY
set -u
mpiexec=$1
sweep=$2
study=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
rows() { tail -n +2 "$1" | sort; }
mpi() { timeout 300 "$mpiexec" -n "$1" "$sweep" "$study" --threads 1 --out "$2" >/dev/null 2>&1; }

timeout 300 "$sweep" "$study" --out "$dir/full.csv" >/dev/null 2>&1 || { echo "FAIL: single-process run"; exit 1; }
mpi 1 "$dir/one.csv" || { echo "FAIL: 1 rank"; fail=1; }
mpi 2 "$dir/two.csv" || { echo "FAIL: 2 ranks"; fail=1; }
diff <(rows "$dir/full.csv") <(rows "$dir/one.csv") >/dev/null || { echo "FAIL: 1 rank differs"; fail=1; }
diff <(rows "$dir/full.csv") <(rows "$dir/two.csv") >/dev/null || { echo "FAIL: 2 ranks differ"; fail=1; }

setsid timeout 300 "$mpiexec" -n 2 "$sweep" "$study" --threads 1 --out "$dir/killed.csv" >/dev/null 2>&1 &
leader=$!
for _ in $(seq 1 1000); do
    [ -f "$dir/killed.csv" ] && [ "$(wc -l < "$dir/killed.csv")" -gt 10 ] && break
    sleep 0.02
done
# Every process of the job at once, as a batch scheduler kills a job: mpirun and each rank (the
# ranks run in process groups of their own).
pkill -9 -f -- "--out $dir/killed.csv" 2>/dev/null
kill -9 -- "-$leader" 2>/dev/null
wait "$leader" 2>/dev/null
for _ in $(seq 1 100); do pgrep -f -- "--out $dir/killed.csv" >/dev/null || break; sleep 0.05; done
partial=$(($(wc -l < "$dir/killed.csv") - 1))
total=$(($(wc -l < "$dir/full.csv") - 1))
echo "2 ranks killed after $partial of $total rows"
[ "$partial" -lt "$total" ] || { echo "FAIL: the run finished before the kill"; fail=1; }
mpi 2 "$dir/killed.csv" || { echo "FAIL: resumed 2-rank run"; fail=1; }
diff <(rows "$dir/full.csv") <(rows "$dir/killed.csv") >/dev/null || { echo "FAIL: killed + resumed rows differ"; fail=1; }
[ "$(cut -d, -f1 "$dir/killed.csv" | sort | uniq -d | wc -l)" -eq 0 ] || { echo "FAIL: a point was done twice"; fail=1; }
[ "$fail" -eq 0 ] && echo "MPI ranks and kill/resume checks passed"
exit $fail
