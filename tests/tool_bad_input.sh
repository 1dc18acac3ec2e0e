#!/usr/bin/env bash
# Every bad-input class through a tool: exit status 2, a one-line message naming the key, and
# no output file left behind. Usage: tool_bad_input.sh TOOL [extra args before the scene...]
set -u
tool=$1; shift
extra=("$@")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
good='{"model": {"Nm": 3, "fc": 10, "eps": 0.5, "e_r": 0.5}, "excitation": {"f_r": 1.0}, "run": {"periods": 5}}'
echo "$good" > "$dir/good.json"
echo '{"model": {"Nm": 3,' > "$dir/malformed.json"
echo '{"model": {"Nm": 3, "springiness": 2}}' > "$dir/unknown.json"
echo '{"model": {"Nm": 0}}' > "$dir/range.json"
echo '{"model": {"fc": 1e999}}' > "$dir/inf.json"
echo '{"model": {"Nm": "three"}}' > "$dir/type.json"
fail=0
check() { # name, expected key fragment, args...
    local name=$1 key=$2; shift 2
    local out="$dir/out_$name"
    "$tool" "${extra[@]}" "$@" --out "$out" >"$dir/stdout" 2>"$dir/stderr"
    local rc=$?
    local lines; lines=$(wc -l < "$dir/stderr")
    if [ "$rc" -ne 2 ]; then echo "FAIL $name: exit $rc, expected 2"; fail=1; fi
    if [ "$lines" -ne 1 ]; then echo "FAIL $name: $lines stderr lines, expected 1"; cat "$dir/stderr"; fail=1; fi
    if ! grep -q -- "$key" "$dir/stderr"; then echo "FAIL $name: message lacks '$key'"; cat "$dir/stderr"; fail=1; fi
    if ls "$dir" | grep -q "^out_$name"; then echo "FAIL $name: output left behind"; fail=1; fi
}
check malformed "malformed JSON" "$dir/malformed.json"
check unknown "model.springiness: unknown key" "$dir/unknown.json"
check range "model.Nm" "$dir/range.json"
check inf "model.fc: a number must be 0 or finite" "$dir/inf.json"
check type "model.Nm" "$dir/type.json"
check nan "model.eps" "$dir/good.json" --set model.eps=nan
check negative "model.fc" "$dir/good.json" --set model.fc=-3
check periods "run.periods" "$dir/good.json" --set run.periods=0
check unreadable "cannot read" "$dir/missing.json"
check option "see --help" "$dir/good.json" --no-such-option
# A newline in the user's own text (here a file name) is escaped: it split the message.
check newline 'no\\nsuch.json: cannot read' "$dir/no"$'\n'"such.json"
# A long message is shortened between whole characters and whole escapes: three names of 3-byte
# letters, offset by 0, 1 and 2 bytes, put one of the cuts inside a letter if any can.
euro=$(printf '\xe2\x82\xac%.0s' $(seq 100))
for pad in "" x xx; do
    check "long$pad" "cannot read" "$dir/$pad$euro/$euro/$euro/$euro/$euro"
    if ! iconv -f UTF-8 -t UTF-8 "$dir/stderr" > /dev/null 2>&1; then
        echo "FAIL long$pad: the shortened message is not valid UTF-8"; fail=1
    fi
done
controls=$(printf '\x01%.0s' $(seq 250))
for pad in "" x xx x3; do
    check "escapes$pad" "cannot read" "$dir/$pad$controls"
    if sed 's/\\x01//g' "$dir/stderr" | grep -q '\\'; then
        echo "FAIL escapes$pad: an escape was cut"; cat "$dir/stderr"; fail=1
    fi
done
[ "$fail" -eq 0 ] && echo "all bad-input checks passed"
exit $fail
