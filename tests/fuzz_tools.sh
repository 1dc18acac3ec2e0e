#!/usr/bin/env bash
# Seeded fuzz of every tool's input: malformed scenes, bad values for every scene key, bad flags.
# Each case must end with exit status 2, exactly one line on stderr naming what was wrong, and no
# output left behind. Usage: fuzz_tools.sh BIN_DIR [SEED] [CASES]
set -u
bin=$(cd "$1" && pwd)
RANDOM=${2:-20261123}
cases=${3:-240}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1

# Tools taking a scene, with the flags each needs to stay quick; every one writes to out/.
scene_tools=(
    "gapchain-sim|--out out/r.json"
    "gapchain-poincare|--no-plot --out out/p"
    "gapchain-spectrum|--no-plot --out out/s"
    "gapchain-lyapunov|--no-plot --out out/l.json"
    "gapchain-classify|--out out/c.json"
    "gapchain-accuracy|--no-plot --out out/a"
    "gapchain-bifurcation|--steps 2 --no-plot --out out/b"
    "gapchain-bounds|--out out/bounds.json"
    "gapchain-modes|--out out/m.json"
)
# Scene keys with values each refuses (out of range, wrong type, non-finite, wrong shape).
bad_values=(
    'model.Nm|0' 'model.Nm|-3' 'model.Nm|2.5' 'model.Nm|"five"' 'model.Nm|1e7' 'model.Nm|null'
    'model.fc|0' 'model.fc|-1' 'model.fc|1e10' 'model.fc|"x"' 'model.fc|[1]'
    'model.eps|-0.1' 'model.eps|101' 'model.eps|true'
    'model.e_r|-1' 'model.e_r|1e7' 'model.e_r|{}'
    'excitation.f_r|0' 'excitation.f_r|-2' 'excitation.f_r|1e5' 'excitation.f_r|"1"'
    'run.periods|0' 'run.periods|-5' 'run.periods|1.5' 'run.periods|2e9'
    'run.transient_periods|-1' 'run.transient_periods|"some"' 'run.transient_periods|5000'
    'run.tolerance|0' 'run.tolerance|1' 'run.tolerance|1e-13' 'run.scheme|"euler"'
    'run.scheme|3' 'run.step|0' 'run.step|-1e-3' 'run.steady_state|"yes"'
    'run.max_steady_period|0' 'run.max_work|0' 'run.max_work|1e16'
    'model.contact_law|"cubic"' 'model.contact_damping|-1' 'model.mass|[1,2]'
    'model.clearance|[0.1]' 'model.mass|"heavy"' 'initial.u|[1]' 'initial.v|"fast"'
    'output.trajectory_every|0' 'model.springiness|2' 'run.speed|3' 'excitation.type|"quake"'
)
# Whole scene files that are not a scene.
bad_files=(
    '{"model": {"Nm": 3,'
    '[1, 2, 3]'
    '42'
    'null'
    '{"model": {"Nm": 3}} trailing'
    '{"model": {"Nm": 3, "Nm": 4}}'
    '{"model": 5}'
    '{"units": "imperial"}'
    '{"model": {"fc": NaN}}'
    '{"model": {"fc": 1e999}}'
    ''
)
# Flag values each tool refuses.
bad_flags=(
    "gapchain-sim|--trajectory|/proc/nowhere/t.csv"
    "gapchain-poincare|--phase|1.5"
    "gapchain-poincare|--section|sideways"
    "gapchain-spectrum|--segment|3"
    "gapchain-spectrum|--variable|q7"
    "gapchain-lyapunov|--count|-2"
    "gapchain-classify|--transient|-4"
    "gapchain-accuracy|--schemes|euler"
    "gapchain-accuracy|--tolerances|0"
    "gapchain-bifurcation|--param|mass"
    "gapchain-bifurcation|--from|nan"
    "gapchain-bifurcation|--record|0"
    "gapchain-bounds|--no-such-flag|1"
    "gapchain-modes|--Nm|-1"
    "gapchain-modes|--end|middle"
)

good='{"model": {"Nm": 3, "fc": 10, "eps": 0.5, "e_r": 0.5}, "excitation": {"f_r": 1.0}, "run": {"periods": 5}}'
echo "$good" >good.json
fail=0
ran=0
pick() { # ARRAY_NAME -> one element
    local -n array=$1
    echo "${array[$((RANDOM % ${#array[@]}))]}"
}
check() { # DESCRIPTION CMD...
    local what=$1
    shift
    rm -rf out
    mkdir out
    timeout -s KILL 30 "$@" >stdout 2>stderr
    local rc=$?
    ran=$((ran + 1))
    local problem=""
    [ "$rc" -eq 2 ] || problem="exit $rc"
    [ "$(wc -l <stderr)" -eq 1 ] || problem="$problem, $(wc -l <stderr) stderr lines"
    [ -z "$(ls -A out)" ] || problem="$problem, left $(ls -A out | tr '\n' ' ')"
    if [ -n "$problem" ]; then
        echo "FAIL ($what): $problem: $*"
        head -n 3 stderr
        fail=$((fail + 1))
    fi
}

for ((k = 0; k < cases; k++)); do
    entry=$(pick scene_tools)
    tool=${entry%%|*}
    read -r -a flags <<<"${entry#*|}"
    case $((RANDOM % 4)) in
    0 | 1)
        kv=$(pick bad_values)
        key=${kv%%|*}
        value=${kv#*|}
        # gapchain-modes reads only the model; bounds and modes take the reduced row.
        if [ "$tool" = gapchain-modes ] || [ "$tool" = gapchain-bounds ]; then
            case $key in model.Nm | model.fc | model.eps | model.e_r | model.springiness) ;; *) key=model.Nm value=0 ;; esac
        fi
        check "$key=$value" "$bin/$tool" good.json --set "$key=$value" "${flags[@]}"
        ;;
    2)
        printf '%s' "$(pick bad_files)" >bad.json
        check "file $(head -c 40 bad.json)" "$bin/$tool" bad.json "${flags[@]}"
        ;;
    3)
        entry=$(pick bad_flags)
        tool=${entry%%|*}
        rest=${entry#*|}
        flag=${rest%%|*}
        value=${rest#*|}
        for e in "${scene_tools[@]}"; do [ "${e%%|*}" = "$tool" ] && read -r -a flags <<<"${e#*|}"; done
        check "$flag $value" "$bin/$tool" good.json "${flags[@]}" "$flag" "$value"
        ;;
    esac
done
echo "$ran cases, $fail failed"
[ "$fail" -eq 0 ] && echo "fuzz: every case refused cleanly"
exit $((fail > 0))
