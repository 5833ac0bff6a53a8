#!/usr/bin/env bash
# The target build's programs against the host build's, on this machine (docs/targets.md):
#   cross_equal.sh CHECK SOURCE HOST_BIN TARGET_BIN WORK EMULATOR...
# CHECK is one of
#   renders  the cluster and the 13 feature scenes, converted once by the host's meter-convert,
#            drawn offscreen by each meter-view (EGL): the same pixels (compare_images.py)
#   decode   a real drive (ft86_motec) decoded by each meter-controller: the same CSV; the demo drive
#            run through each controller's whole path (decode, mapping, conditioning) into a link
#            recording, whose values are written losslessly: the same file, so the same bits
#   link     the wire across the architectures: one's meter-linkplay serves a recording with a link
#            key (every frame MAC-tagged) to the other's meter-linkdump, both ways, and the recorded
#            state equals the served one; the recordings both controllers made of the same drive
#            are the same bytes, and each drawn by the other side's meter-view: the same frames
# EMULATOR runs a target program (qemu-aarch64-static). Exit 0 when every comparison holds; each
# difference is printed with the file it is in. Scenes converted once are kept in WORK/../converted
# (made anew when the scene, its config or meter-convert is newer).
set -euo pipefail
(($# >= 6)) || { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
check=$1 src=$2 host=$3 target=$4 work=$5
shift 5
emu=("$@")
here=$(cd "$(dirname "$0")" && pwd)
shared="$src/../shared"
rm -rf "$work"
mkdir -p "$work"
converted="$work/../converted"
mkdir -p "$converted"
py=${METER_PYTHON:-/usr/bin/python3}  # Debian's, with python3-pil (scripts/deps/test.list)
fail=0
failed() { echo "cross_equal $check: $*" >&2; fail=1; }
host_run() { "$host/$1" "${@:2}"; }
target_run() { "${emu[@]}" "$target/$1" "${@:2}"; }
convert() {  # NAME GLB CONFIG: the host's meter-convert, once; prints the package's path
  local msp="$converted/$1.msp"
  if [[ ! -s $msp || $2 -nt $msp || $3 -nt $msp || $host/meter-convert -nt $msp ]]; then
    host_run meter-convert "$2" --config "$3" -o "$msp.part" -q >"$work/convert-$1.log" 2>&1 ||
      { failed "meter-convert $1 failed: $(tail -3 "$work/convert-$1.log")"; return 1; }
    mv "$msp.part" "$msp"
  fi
  echo "$msp"
}
# Both architectures draw with the same Mesa driver (GALLIUM_DRIVER, default llvmpipe), one sample a
# pixel: the arm64 llvmpipe (Mesa 22.3.6) under qemu-user crashed (SIGSEGV) drawing with 4 samples, and
# a pixel may differ by one level, Mesa's own arm64 build rounding differently (docs/targets.md).
export GALLIUM_DRIVER=${GALLIUM_DRIVER:-llvmpipe}

run_both() {  # NAME ARGS...: the program on both, each output in WORK/{host,target}
  local name=$1; shift
  mkdir -p "$work/host" "$work/target"
  host_run "$name" "$@" >"$work/host.out" 2>"$work/host.err" || { failed "host $name failed: $(tail -3 "$work/host.err")"; return 1; }
  target_run "$name" "$@" >"$work/target.out" 2>"$work/target.err" || { failed "target $name failed: $(tail -3 "$work/target.err")"; return 1; }
}

case $check in
renders)
  scenes=("$src/scenes/cluster/cluster.glb:$src/scenes/cluster/cluster.scene.json")
  for dir in "$src"/scenes/features/*/; do
    name=$(basename "$dir")
    scenes+=("$dir$name.glb:${dir}scene.json")
  done
  ((${#scenes[@]} == 14)) || failed "expected the cluster and 13 feature scenes, found ${#scenes[@]}"
  # The cluster driving (needles, gear, odometer, two lamps); a feature scene in its config's state.
  cluster_state=(--set Vehicle.Speed=100 --set Vehicle.Powertrain.CombustionEngine.Speed=3000
                 --set Vehicle.Powertrain.FuelSystem.RelativeLevel=60 --set Vehicle.Powertrain.CombustionEngine.ECT=90
                 --set Vehicle.Powertrain.Transmission.CurrentGear=4 --set Vehicle.TraveledDistance=12345
                 --set Vehicle.TripMeterReading=123.4 --set Vehicle.Exterior.AirTemperature=21
                 --set Cluster.Telltale.TurnLeft=1 --set Cluster.Telltale.LowBeam=1)
  for pair in "${scenes[@]}"; do
    glb=${pair%%:*} config=${pair#*:}
    name=$(basename "$glb" .glb)
    msp=$(convert "$name" "$glb" "$config") || { fail=1; continue; }
    state=()
    [[ $name == cluster ]] && state=("${cluster_state[@]}")
    for side in host target; do
      "${side}_run" meter-view --scene "$msp" --backend egl --msaa 1 --out "$work/$side" --png "$name.png" "${state[@]}" \
        >"$work/$side-$name.log" 2>&1 || failed "$side meter-view $name failed: $(tail -3 "$work/$side-$name.log")"
    done
    # One level: llvmpipe's x86-64 build runs SSE code (hand-written and generated) where its arm64
    # build runs generic code, rounding a colour's last bit apart. Two for bump: its normal map's
    # sharp highlight turns the same roundings of the sampled normal into two levels; its mip chain
    # is meter's, equal on both (the driver's differs by up to 4 levels a texel and gave 28).
    # docs/targets.md, "Renders".
    bound=1
    [[ $name == bump ]] && bound=2
    "$py" "$here/compare_images.py" --max-level "$bound" "$work/host/$name.png" "$work/target/$name.png" || fail=1
  done
  ;;
decode)
  run_both meter-controller decode --dbc "$shared/data/can/ft86_motec/sample_can_spec.dbc" \
    "$shared/data/can/ft86_motec/can_sample.log" || true
  if [[ -s $work/host.out ]]; then
    cmp "$work/host.out" "$work/target.out" || failed "the ft86 drive decodes differently (host.out, target.out in $work)"
    echo "cross_equal decode: ft86 drive, $(($(wc -l <"$work/host.out") - 1)) decoded values, equal"
  fi
  for side in host target; do
    "${side}_run" meter-controller run --dbc "$src/controller/vehicles/demo/demo.dbc" \
      --map "$src/controller/vehicles/demo/demo.map" --input "log:$src/vcan/logs/demo-drive.log" --replay fast \
      --exit-at-end --record "$work/$side.rec" --link "unix:$work/$side.sock" --state-dir "$work/$side-state" \
      >"$work/$side-run.log" 2>&1 || failed "$side meter-controller run failed: $(tail -3 "$work/$side-run.log")"
  done
  cmp "$work/host.rec" "$work/target.rec" || failed "the demo drive's published values differ (host.rec, target.rec in $work)"
  echo "cross_equal decode: demo drive, $(grep -c . "$work/host.rec") recorded link messages, equal"
  ;;
link)
  # A recording made by each side's controller: 600 CAN frames (2.8 s) of the demo drive at 107 to
  # 120 km/h, so the needles and readouts move in every frame drawn below.
  sed -n '5001,5600p' "$src/vcan/logs/demo-drive.log" >"$work/drive.log"
  for side in host target; do
    "${side}_run" meter-controller run --dbc "$src/controller/vehicles/demo/demo.dbc" \
      --map "$src/controller/vehicles/demo/demo.map" --input "log:$work/drive.log" --replay fast --exit-at-end \
      --record "$work/$side.rec" --link "unix:$work/$side-rec.sock" --state-dir "$work/$side-state" \
      >"$work/$side-record.log" 2>&1 || failed "$side meter-controller run failed: $(tail -3 "$work/$side-record.log")"
  done
  # Published values are the same bits on both (as in decode): the same recording, byte for byte.
  cmp "$work/host.rec" "$work/target.rec" || failed "the two controllers' recordings differ (host.rec, target.rec in $work)"
  printf '7 %s\n' "$(od -An -tx1 -N32 /dev/urandom | tr -d ' \n')" >"$work/link.key"
  chmod 600 "$work/link.key"
  # The wire: SERVER's meter-linkplay serves SERVER's recording, CLIENT's meter-linkdump records it.
  for way in host:target target:host; do
    server=${way%%:*} client=${way#*:}
    sock="$work/$server-serves.sock" got="$work/$client-received.rec"
    "${server}_run" meter-linkplay "$work/$server.rec" --link "unix:$sock" --speed max --linger 0.5 \
      --key-file "$work/link.key" >"$work/$server-linkplay.log" 2>&1 &
    play=$!
    "${client}_run" meter-linkdump --link "unix:$sock" --key-file "$work/link.key" -q -o "$got" --until-closed \
      --duration 120 >"$work/$client-linkdump.log" 2>&1 || failed "$client meter-linkdump failed: $(tail -3 "$work/$client-linkdump.log")"
    wait "$play" || failed "$server meter-linkplay failed: $(tail -3 "$work/$server-linkplay.log")"
    "$py" "$here/recording_state.py" "$work/$server.rec" "$got" || failed "$server -> $client: the state differs"
  done
  # Each side's recording drawn by the other side's meter-view (the cluster converted by the host),
  # frames at 0, 1 and 2 s, compared with each other. The recordings being the same bytes, each
  # view's frames are also what it draws of its own side's recording, so one emulated view suffices.
  msp=$(convert cluster "$src/scenes/cluster/cluster.glb" "$src/scenes/cluster/cluster.scene.json") || exit 1
  for play in target.rec:host host.rec:target; do
    rec=${play%%:*} side=${play#*:}
    out="$work/play-${rec%.rec}-by-$side"
    "${side}_run" meter-view --scene "$msp" --backend egl --msaa 1 --play "$work/$rec" --fps 1 \
      --duration 2 --dump-every 1 --out "$out" >"$out.log" 2>&1 ||
      failed "$side meter-view --play $rec failed: $(tail -3 "$out.log")"
  done
  frames=0
  for png in "$work/play-target-by-host"/*.png; do
    [[ -e $png ]] || break
    "$py" "$here/compare_images.py" --max-level 1 "$png" "$work/play-host-by-target/$(basename "$png")" || fail=1
    frames=$((frames + 1))
  done
  ((frames >= 3)) || failed "$frames frames of the recordings were dumped, expected 3"
  ;;
*)
  echo "cross_equal: no check '$check' (renders, decode, link)" >&2
  exit 2
  ;;
esac
exit "$fail"
