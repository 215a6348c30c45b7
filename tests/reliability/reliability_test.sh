#!/usr/bin/env bash
# The guarantees of docs/reliability.md that issue #37 found broken, each a named check against
# adapters that misbehave (tests/reliability/hostile_adapter.py) and files made here to be hostile:
# an outside engine's bytes, framing, processes and timing cost only its own records; no user file
# under --out or a staging folder is deleted; bad input is one line and exit 2, never exit 3.
# Prints PASS or FAIL per check; exit 1 when any fails.
set -u
bin=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
here=$(cd "$(dirname "$0")" && pwd)
tools="$here/../tools"
tmp=$(mktemp -d)
mnt=""
cleanup() {
  [ -n "$mnt" ] && umount "$mnt" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fails=0
passes=0
pass() { echo "PASS $1"; passes=$((passes + 1)); }
fail() { echo "FAIL $1: $2"; fails=$((fails + 1)); }

# A registration of the hostile adapter in mode M in folder D, as configuration h-M.
register() {  # register DIR MODE [EXTRA_ARG]
  mkdir -p "$1"
  python3 - "$here/hostile_adapter.py" "$1" "$2" "${3:-}" <<'PY'
import json, sys
script, folder, mode, extra = sys.argv[1:5]
command = [sys.executable, script, mode] + ([extra] if extra else [])
json.dump({"name": f"h-{mode}", "command": command, "description": f"misbehaves: {mode}", "color": "#7f7f7f"},
          open(f"{folder}/h-{mode}.json", "w"))
PY
}

# One line on stderr naming PATTERN, exit 2, nothing on stdout.
bad_input() {  # bad_input NAME PATTERN COMMAND...
  local name="$1" pattern="$2"
  shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [ "$got" -ne 2 ] || [ "$(wc -l <"$tmp/err")" -ne 1 ] || ! grep -qF -- "$pattern" "$tmp/err" || [ -s "$tmp/out" ]; then
    fail "$name" "exit $got, wanted 2 and one line with '$pattern': $(head -c 400 "$tmp/err") $(head -c 200 "$tmp/out")"
  else
    pass "$name"
  fi
}

# The records of RESULTS of configuration ENGINE: each an error whose one-line message holds TEXT.
errors_say() {  # errors_say NAME RESULTS ENGINE TEXT...
  local name="$1" results="$2" engine="$3"
  shift 3
  if python3 - "$results" "$engine" "$@" >"$tmp/why" 2>&1 <<'PY'
import json, sys
results, engine, texts = sys.argv[1], sys.argv[2], sys.argv[3:]
runs = [r for r in json.load(open(results))["runs"] if r["engine"] == engine]
assert runs, f"no runs of {engine}"
for r in runs:
    m = r["message"]
    assert r["status"] == "error", f"{r['scenario']}: {r['status']} ({m!r}), wanted an error record"
    assert "\n" not in m and "\0" not in m, f"{r['scenario']}: not one line: {m!r}"
    for t in texts:
        assert t in m, f"{r['scenario']}: {m!r} does not say {t!r}"
PY
  then pass "$name"; else fail "$name" "$(tail -c 600 "$tmp/why")"; fi
}

# ODE's records in RESULTS equal those of a suite of ODE alone (timings aside).
ode_unchanged() {  # ode_unchanged NAME RESULTS REFERENCE
  if python3 - "$tools" "$2" "$3" >"$tmp/why" 2>&1 <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from same_records import expand_references, first_difference, strip
a, b = (sorted((r for r in expand_references(json.load(open(p)))["runs"] if r["engine"] == "ode"), key=lambda r: r["scenario"]) for p in sys.argv[2:4])
assert a, "no runs of ode"
d = first_difference(strip(a), strip(b), "ode runs")
assert d is None, d
PY
  then pass "$1"; else fail "$1" "$(tail -c 600 "$tmp/why")"; fi
}

suite() {  # suite OUT ENGINE_DIR ENGINES FILTER [ARGS...]: validate without sweeps or report; status in $status
  local out="$1" dir="$2" engines="$3" filter="$4"
  shift 4
  status=0
  "$bin" validate --engine-dir "$dir" --engines "$engines" --filter "$filter" --no-sweeps --no-report --out "$out" "$@" >"$out.log" 2>&1 || status=$?
}

# ---- reference: ode alone ----
mkdir -p "$tmp/none"
suite "$tmp/ref" "$tmp/none" ode 'car.circle,disks.linear' --timeout 30

# ---- item 1: an adapter's bytes are data, never the suite's end ----
for m in latin1-start latin1-hello latin1-knob latin1-step latin1-die; do register "$tmp/bytes" "$m"; done
"$bin" engines --json --engine-dir "$tmp/bytes" >"$tmp/engines.json" 2>"$tmp/engines.err"
st=$?
if [ "$st" -eq 0 ] && python3 - "$tmp/engines.json" <<'PY'
import json, sys
d = {e["name"]: e for e in json.load(open(sys.argv[1]))}
why = lambda n: d[n]["settings"].get("unavailable", "") if isinstance(d[n]["settings"], dict) else ""
for n in ["h-latin1-start", "h-latin1-hello", "h-latin1-knob"]:
    assert d[n]["library"] == "unavailable" and why(n), (n, json.dumps(d[n])[:300])
assert "L?ser nicht gefunden" in why("h-latin1-start"), why("h-latin1-start")
assert d["h-latin1-step"]["library"] == "Hostile", d["h-latin1-step"]
PY
then pass "bytes-engines-json"; else fail "bytes-engines-json" "exit $st: $(head -c 400 "$tmp/engines.err")"; fi
suite "$tmp/bytes-out" "$tmp/bytes" ode,h-latin1-start,h-latin1-hello,h-latin1-knob,h-latin1-step,h-latin1-die 'car.circle,disks.linear' --timeout 30 --jobs 2
if [ "$status" -eq 1 ] && [ -s "$tmp/bytes-out/results.json" ]; then pass "bytes-suite-written"; else fail "bytes-suite-written" "exit $status: $(tail -c 400 "$tmp/bytes-out.log")"; fi
if [ -s "$tmp/bytes-out/results.json" ]; then
  errors_say bytes-start-unavailable "$tmp/bytes-out/results.json" h-latin1-start "engine 'h-latin1-start'" "Modul f?r den L?ser nicht gefunden"
  errors_say bytes-hello-unavailable "$tmp/bytes-out/results.json" h-latin1-hello "engine 'h-latin1-hello'" "Gr??e Fehler"
  errors_say bytes-knob-unavailable "$tmp/bytes-out/results.json" h-latin1-knob "engine 'h-latin1-knob' (hello)" "not one JSON object"
  errors_say bytes-step-record "$tmp/bytes-out/results.json" h-latin1-step "engine 'h-latin1-step' (step)" "Schritt fehlgeschlagen: ???"
  errors_say bytes-die-record "$tmp/bytes-out/results.json" h-latin1-die "exited with status 3" "L?ser abgest?rzt"
  ode_unchanged bytes-ode-unchanged "$tmp/bytes-out/results.json" "$tmp/ref/results.json"
fi

# ---- item 3: a reply is tied to its request ----
for m in extra-build extra-hello no-id wrong-id string-id; do register "$tmp/framing" "$m"; done
suite "$tmp/framing-out" "$tmp/framing" ode,h-extra-build,h-extra-hello,h-no-id,h-wrong-id,h-string-id 'car.circle,car.cycle,disks.linear' --timeout 30 --jobs 1
if [ -s "$tmp/framing-out/results.json" ]; then
  # Each run served by the one process of h-extra-build is an error naming the number, not a run judged on physics.
  # Found as a line waiting before the next request, or as a reply numbered for the request before.
  errors_say framing-extra-line "$tmp/framing-out/results.json" h-extra-build "engine 'h-extra-build'" "out of step"
  errors_say framing-extra-hello "$tmp/framing-out/results.json" h-extra-hello "engine 'h-extra-hello'" "out of step"
  errors_say framing-old-adapter "$tmp/framing-out/results.json" h-no-id "without its request's number" "protocol 2"
  errors_say framing-wrong-id "$tmp/framing-out/results.json" h-wrong-id "(step)" "numbered"
  errors_say framing-string-id "$tmp/framing-out/results.json" h-string-id "(step)" "number"
  python3 - "$tmp/framing-out/results.json" "$tmp/ref/results.json" "$tools" >"$tmp/why" 2>&1 <<'PY' && pass framing-ode-unchanged || fail framing-ode-unchanged "$(tail -c 400 "$tmp/why")"
import json, sys
sys.path.insert(0, sys.argv[3])
from same_records import expand_references, first_difference, strip
a = {r["scenario"]: r for r in expand_references(json.load(open(sys.argv[1])))["runs"] if r["engine"] == "ode"}
b = {r["scenario"]: r for r in expand_references(json.load(open(sys.argv[2])))["runs"] if r["engine"] == "ode"}
for s in b:
    d = first_difference(strip(a[s]), strip(b[s]), s)
    assert d is None, d
assert a["car.cycle"]["status"] == "pass", a["car.cycle"]
PY
else
  fail framing-suite "exit $status: $(tail -c 400 "$tmp/framing-out.log")"
fi

# ---- item 10: NUL bytes do not cut messages ----
for m in nul-error nul-raw; do register "$tmp/nul" "$m"; done
suite "$tmp/nul-out" "$tmp/nul" h-nul-error,h-nul-raw 'car.circle' --timeout 30
if [ -s "$tmp/nul-out/results.json" ]; then
  errors_say nul-in-error-reply "$tmp/nul-out/results.json" h-nul-error "before?after the NUL"
  errors_say nul-raw-in-reply "$tmp/nul-out/results.json" h-nul-raw "after the NUL"
else
  fail nul-suite "exit $status: $(tail -c 400 "$tmp/nul-out.log")"
fi

# ---- item 5: an adapter's grandchild holding its output neither hangs the run nor survives ----
for m in grandchild grandchild-setsid; do
  register "$tmp/gc-$m" "$m" "$tmp/$m.pid"
  # Not hung: the record names the adapter's exit, not the reply timeout that a hang would reach.
  suite "$tmp/gc-$m-out" "$tmp/gc-$m" "h-$m" 'car.circle' --timeout 60
  if [ -s "$tmp/gc-$m-out/results.json" ] && ! grep -q 'no reply within' "$tmp/gc-$m-out/results.json"; then
    errors_say "$m-record" "$tmp/gc-$m-out/results.json" "h-$m" "exited with status 5"
  else
    fail "$m-record" "no record, or the run waited out its reply timeout; exit $status"
  fi
  pid=$(cat "$tmp/$m.pid" 2>/dev/null || echo "")
  sleep 0.5
  # Ended: gone, or a zombie its new parent has not reaped (a container's init may never reap).
  state=$(sed 's/.*) //' "/proc/$pid/stat" 2>/dev/null | cut -d' ' -f1)
  if [ -n "$pid" ] && { [ -z "$state" ] || [ "$state" = Z ]; }; then pass "$m-ended"; else fail "$m-ended" "grandchild '$pid' still runs ($state)"; kill "$pid" 2>/dev/null; fi
done

# ---- item 6: a signal ends the wait for a hello ----
register "$tmp/slow" slow-hello
for sig in TERM INT; do
  for cmd in engines validate; do
    args=("$cmd" --engine-dir "$tmp/slow")
    [ "$cmd" = validate ] && args+=(--engines h-slow-hello --filter car.circle --no-report --out "$tmp/slow-out")
    "$bin" "${args[@]}" >"$tmp/slow.log" 2>&1 &
    lc=$!
    sleep 1.5
    kill -"$sig" "$lc"
    wait "$lc"
    st=$?
    # The signal ended the wait: its exit status, and no word of the hello's timeout (which a wait
    # that ignored the signal would reach first).
    want=$([ "$sig" = TERM ] && echo 143 || echo 130)
    if [ "$st" -eq "$want" ] && ! grep -q 'no reply within\|timed out' "$tmp/slow.log"; then pass "signal-$sig-$cmd-hello"; else fail "signal-$sig-$cmd-hello" "exit $st (wanted $want): $(tail -c 300 "$tmp/slow.log")"; fi
  done
done
pkill_left=$(pgrep -f "hostile_adapter.py slow-hello" || true)
if [ -z "$pkill_left" ]; then pass "signal-hello-adapter-ended"; else fail "signal-hello-adapter-ended" "adapters left: $pkill_left"; for p in $pkill_left; do kill "$p"; done; fi

# ---- item 8: a relative --engine-dir reaches a registered `liftcheck serve` child ----
mkdir -p "$tmp/rel/reg"
python3 - "$bin" "$tmp/rel/reg/ode-served.json" <<'PY'
import json, sys
json.dump({"name": "ode-served", "command": [sys.argv[1], "serve", "ode"], "description": "ode served", "color": "#aec7e8"}, open(sys.argv[2], "w"))
PY
(cd "$tmp/rel" && "$bin" engines --engine-dir reg) >"$tmp/rel.out" 2>&1
if grep -q '^ode-served  \[ODE ' "$tmp/rel.out"; then pass relative-engine-dir; else fail relative-engine-dir "$(grep -A2 ode-served "$tmp/rel.out" | head -c 400)"; fi
(cd "$tmp/rel" && LIFTCHECK_ENGINE_PATH=reg "$bin" engines) >"$tmp/rel.out" 2>&1
if grep -q '^ode-served  \[ODE ' "$tmp/rel.out"; then pass relative-engine-path; else fail relative-engine-path "$(grep -A2 ode-served "$tmp/rel.out" | head -c 400)"; fi

# ---- item 10: registrations that the docs refuse ----
mkdir -p "$tmp/reg-dup" "$tmp/reg-dup2" "$tmp/reg-nul" "$tmp/reg-nul2"
printf '{"name": "dup", "command": ["python3", "x.py"], "color": "#000000", "name": "dup"}\n' >"$tmp/reg-dup/dup.json"
bad_input registration-key-twice "the key 'name' appears twice" "$bin" list --engine-dir "$tmp/reg-dup"
printf '{"name": "dup2", "command": ["python3"], "color": "#000000", "command": ["sh", "-c", "true"]}\n' >"$tmp/reg-dup2/dup2.json"
bad_input registration-command-twice "the key 'command' appears twice" "$bin" list --engine-dir "$tmp/reg-dup2"
printf '{"name": "nul", "command": ["python3\\u0000 -c evil"], "color": "#000000"}\n' >"$tmp/reg-nul/nul.json"
bad_input registration-command-nul "NUL" "$bin" list --engine-dir "$tmp/reg-nul"
printf '{"name": "nul2", "command": ["python3", "a\\u0000b"], "color": "#000000"}\n' >"$tmp/reg-nul2/nul2.json"
bad_input registration-argument-nul "NUL" "$bin" list --engine-dir "$tmp/reg-nul2"

# ---- item 10: --help and --version to a full standard output ----
for args in "--help" "--version" "run --help" "validate --help"; do
  # shellcheck disable=SC2086
  "$bin" $args >/dev/full 2>"$tmp/err"
  st=$?
  if [ "$st" -eq 2 ] && grep -q "cannot write to standard output" "$tmp/err"; then pass "full-stdout-${args// /-}"; else fail "full-stdout-${args// /-}" "exit $st: $(head -c 200 "$tmp/err")"; fi
done

# ---- item 9: serve to a full standard output ----
printf '{"op": "hello", "protocol": 3, "id": 1}\n{"op": "bye", "id": 2}\n' | "$bin" serve ode >/dev/full 2>"$tmp/err"
st=$?
if [ "$st" -eq 2 ] && grep -q "cannot write to standard output" "$tmp/err" && [ "$(wc -l <"$tmp/err")" -eq 1 ]; then pass serve-full-stdout
else fail serve-full-stdout "exit $st: $(head -c 300 "$tmp/err")"; fi

# ---- item 9: a 300-character name in --out ----
long=$(printf 'a%.0s' $(seq 300))
bad_input out-name-too-long "longer than" "$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/$long"
bad_input out-inner-name-too-long "longer than" "$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/$long/x"

# ---- item 9: merge on shards with wrongly typed fields ----
"$bin" validate --engines analytic --filter 'car.cycle,car.circle' --no-report --shard 1/2 --out "$tmp/s1" >/dev/null 2>&1
"$bin" validate --engines analytic --filter 'car.cycle,car.circle' --no-report --shard 2/2 --out "$tmp/s2" >/dev/null 2>&1
"$bin" merge "$tmp/s1" "$tmp/s2" --no-report --out "$tmp/merged" >"$tmp/merge.log" 2>&1
if [ $? -le 1 ]; then pass merge-good-shards; else fail merge-good-shards "$(tail -c 300 "$tmp/merge.log")"; fi
bad_input merge-out-name-too-long "longer than" "$bin" merge "$tmp/s1" "$tmp/s2" --no-report --out "$tmp/$long"
variant=0
while IFS='|' read -r label expr pattern; do
  variant=$((variant + 1))
  rm -rf "$tmp/sv" && cp -r "$tmp/s1" "$tmp/sv"
  python3 - "$tmp/sv/results.json" "$expr" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
exec(sys.argv[2])
json.dump(j, open(sys.argv[1], "w"))
PY
  bad_input "merge-$label" "$pattern" "$bin" merge "$tmp/sv" "$tmp/s2" --no-report --out "$tmp/merged-$variant"
  [ -e "$tmp/merged-$variant" ] && fail "merge-$label-nothing-written" "'$tmp/merged-$variant' exists"
done <<'EOF'
index-string|j["shard"]["index"] = "1"|shard
total-huge|j["shard"]["total"] = 1e30|shard
total-zero|j["shard"]["total"] = 0|shard
shard-array|j["shard"] = [1, 2]|shard
version-number|j["context"]["liftcheck"]["version"] = 5|liftcheck
liftcheck-array|j["context"]["liftcheck"] = []|liftcheck
set-number|j["context"]["set"] = 3|set
selection-string|j["plan"]["selection"] = "all"|selection
engines-number|j["plan"]["selection"]["engines"] = 7|engines
filter-string|j["plan"]["selection"]["filter"] = "car.*"|filter
sweeps-string|j["plan"]["selection"]["sweeps"] = "no"|sweeps
keys-object|j["plan"]["keys"] = {}|keys
wall-string|j["context"]["wall_s"] = "fast"|wall_s
jobs-string|j["context"]["jobs"] = "two"|jobs
point-number|j["points"] = {"x": 1}|point
EOF

# ---- item 9: report on results files that pass the reader's checks ----
"$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/one" >/dev/null 2>&1
variant=0
while IFS='|' read -r label expr; do
  variant=$((variant + 1))
  python3 - "$tmp/one/results.json" "$tmp/r$variant.json" "$expr" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(j, open(sys.argv[2], "w"))
PY
  "$bin" report "$tmp/r$variant.json" --no-snapshots --out "$tmp/report-$variant" >"$tmp/out" 2>"$tmp/err"
  st=$?
  if [ "$st" -le 1 ] && [ -s "$tmp/report-$variant/index.html" ]; then pass "report-$label"
  elif [ "$st" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && [ ! -e "$tmp/report-$variant" ]; then pass "report-$label"
  else fail "report-$label" "exit $st: $(head -c 300 "$tmp/err")"; fi
done <<'EOF'
runs-only|j = {"runs": []}
no-summary|del j["summary"]
no-context|del j["context"]
summary-strings|j["summary"] = {k: "x" for k in j["summary"]}
context-engines-number|j["context"]["engines"] = 3
sweeps-number|j["sweeps"] = 5
EOF

# ---- item 2: a replaced output folder never takes the user's files with it ----
"$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/src" >/dev/null 2>&1
for sub in plots snapshots snapshots/deep; do
  name=${sub//\//-}
  named="$sub/notes.txt"
  [ "$sub" = snapshots/deep ] && named="snapshots/deep/"  # a folder inside is named as a folder
  rm -rf "$tmp/copied" && mkdir -p "$tmp/copied/$sub"
  cp "$tmp/src/results.json" "$tmp/copied/"  # cp -r out/* dest/: the hidden manifest stays behind
  echo mine >"$tmp/copied/$sub/notes.txt"
  bad_input "out-user-file-in-$name" "$named" "$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/copied"
  if [ -s "$tmp/copied/$sub/notes.txt" ]; then pass "out-user-file-in-$name-kept"; else fail "out-user-file-in-$name-kept" "deleted"; fi
done
# Files named as liftcheck names its own are still the user's where the old results.json does not
# list them: a page, a plot, a snapshot, a results.json.tmp.
for named in my-notes.html plots/mine.svg snapshots/mine.png results.json.tmp; do
  name=$(echo "$named" | tr '/.' '--')
  rm -rf "$tmp/copied" && mkdir -p "$tmp/copied/plots" "$tmp/copied/snapshots"
  cp "$tmp/src/results.json" "$tmp/copied/"
  echo mine >"$tmp/copied/$named"
  bad_input "out-user-named-like-ours-$name" "$named" "$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/copied"
  if [ -s "$tmp/copied/$named" ]; then pass "out-user-named-like-ours-$name-kept"; else fail "out-user-named-like-ours-$name-kept" "deleted"; fi
done
# A stale staging folder (its process gone) with the user's file in a subfolder is not removed.
rm -rf "$tmp/st" && mkdir -p "$tmp/st/.out.partial-999999-abcdef/plots"
printf 'liftcheck-staging pid 999999 start 1\n' >"$tmp/st/.out.partial-999999-abcdef/.liftcheck-staging"
echo mine >"$tmp/st/.out.partial-999999-abcdef/plots/notes.txt"
mkdir -p "$tmp/st/.out.partial-999998-abcdef/snapshots"
printf 'liftcheck-staging pid 999998 start 1\n' >"$tmp/st/.out.partial-999998-abcdef/.liftcheck-staging"
echo junk >"$tmp/st/.out.partial-999998-abcdef/snapshots/x.png"
"$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/st/out" >/dev/null 2>&1
if [ -s "$tmp/st/.out.partial-999999-abcdef/plots/notes.txt" ]; then pass stale-stage-user-file-kept; else fail stale-stage-user-file-kept "deleted"; fi
if [ ! -e "$tmp/st/.out.partial-999998-abcdef" ]; then pass stale-stage-own-removed; else fail stale-stage-own-removed "a stale folder of liftcheck's own files was kept"; fi

# ---- item 4: --update-baseline naming a folder writes nothing ----
for kind in folder link; do
  rm -rf "$tmp/b-$kind" "$tmp/b-$kind.new"
  mkdir -p "$tmp/bdir"
  if [ "$kind" = folder ]; then mkdir "$tmp/b-$kind"; else ln -s "$tmp/bdir" "$tmp/b-$kind"; fi
  before=$(sha256sum "$tmp/src/results.json")
  bad_input "update-baseline-$kind" "--baseline" "$bin" validate --engines analytic --filter car.cycle --no-report --out "$tmp/src" --update-baseline --baseline "$tmp/b-$kind"
  if [ "$(sha256sum "$tmp/src/results.json")" = "$before" ] && [ ! -e "$tmp/b-$kind.new" ]; then pass "update-baseline-$kind-nothing-written"
  else fail "update-baseline-$kind-nothing-written" "--out was replaced or a .new file left"; fi
done

# ---- item 10: a killed renderer: the summary does not point to a report that is not there ----
"$bin" validate --engines analytic --filter 'car.*' --out "$tmp/killed" >"$tmp/killed.log" 2>&1 &
lc=$!
killed=""
for _ in $(seq 600); do
  for c in $(pgrep -P "$lc" 2>/dev/null); do
    if tr '\0' ' ' <"/proc/$c/cmdline" 2>/dev/null | grep -q ' validate '; then kill -9 "$c" && killed=$c; fi
  done
  [ -n "$killed" ] && break
  sleep 0.05
done
wait "$lc"
st=$?
if [ -n "$killed" ] && [ "$st" -eq 1 ] && grep -q "^REPORT .*killed by signal 9" "$tmp/killed.log" && ! grep -q "index.html" "$tmp/killed.log" \
   && [ ! -e "$tmp/killed/index.html" ] && [ -s "$tmp/killed/results.json" ] && ! grep -q "index.html" "$tmp/killed/summary.md"; then
  pass renderer-killed-summary
else
  fail renderer-killed-summary "killed '$killed', exit $st: $(grep -E 'REPORT|report|index' "$tmp/killed.log" | head -c 400)"
fi

# ---- item 7: the renderer runs under a limit, with a clear error past it ----
"$bin" validate --engines analytic --filter 'car.cycle' --report-memory-limit 64 --out "$tmp/lim" >"$tmp/lim.log" 2>&1
st=$?
if [ "$st" -eq 1 ] && grep -q "^REPORT .*more than its limit of 64 MiB" "$tmp/lim.log" && [ -s "$tmp/lim/results.json" ]; then pass renderer-memory-limit
else fail renderer-memory-limit "exit $st: $(grep -E 'REPORT|error' "$tmp/lim.log" | head -c 400)"; fi
bad_input renderer-memory-limit-too-small "--report-memory-limit" "$bin" validate --engines analytic --filter car.cycle --report-memory-limit 0 --out "$tmp/lim0"

# ---- item 10: a full mount point says so (ENOSPC), and keeps the old output ----
mkdir -p "$tmp/mnt"
if mount -t tmpfs -o size=600k tmpfs "$tmp/mnt" 2>/dev/null; then
  mnt="$tmp/mnt"
  "$bin" validate --engines analytic --filter car.cycle --no-report --out "$mnt" >/dev/null 2>&1
  before=$(sha256sum "$mnt/results.json")
  "$bin" validate --engines analytic --filter 'car.*' --out "$mnt" >"$tmp/out" 2>"$tmp/err"
  st=$?
  if [ "$st" -eq 2 ] && grep -q "No space left on device" "$tmp/err" && ! grep -q "Input/output error" "$tmp/err" && [ "$(sha256sum "$mnt/results.json")" = "$before" ]; then
    pass full-mount-point-enospc
  else
    fail full-mount-point-enospc "exit $st: $(head -c 400 "$tmp/err")"
  fi
  umount "$mnt" && mnt=""
else
  echo "SKIP full-mount-point-enospc (mounting a tmpfs needs root)"
fi

echo "reliability: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
