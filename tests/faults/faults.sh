#!/usr/bin/env bash
# The fault-injection tests (spec §10: "an output file is either written whole or
# not touched"; issue #18). Each case gives snell an old output file, makes the
# write fail in one way, and asserts the exit status, the message, the old file's
# bytes and that no temporary is left beside it.
#   faults.sh SNELL FAULT_SHIM SOURCE_DIR
# Faults: the LD_PRELOAD shim (fault_shim.cpp) for write/fsync/close/rename errors,
# short writes and signals in the write phase; a real full disk (a small tmpfs in
# a private mount namespace, when this runs as root and may mount); SIGTERM and
# SIGINT during the render; symlinks and modes; outputs that are inputs.
set -uo pipefail
snell="$1"
shim="$2"
src="$3"
tmp="$(mktemp -d /tmp/snell-faults.XXXXXX)"
trap 'rm -rf "$tmp"' EXIT
# The resident image servers of these runs (runtime/image_server.hpp) are this
# script's own, and end soon after it (their socket's folder goes with $tmp).
export SNELL_IMAGE_SERVER_DIR="$tmp/servers" SNELL_IMAGE_SERVER_IDLE=5
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
scene="$src/examples/showcase.scn"
small=(--res 96x64 --spp 1 --quiet)

# old_file DIR NAME: an old output with known bytes.
old_file() { printf 'old bytes of %s\n' "$2" > "$1/$2"; }
# untouched DIR NAME: its bytes are still the old ones.
untouched() {
  printf 'old bytes of %s\n' "$2" | cmp -s - "$1/$2" || fail "$CASE: $1/$2 was changed"
}
# no_leftovers DIR: no temporary of Snell's is left in DIR.
no_leftovers() {
  local left
  left="$(ls -A "$1" | grep -F .snell-tmp- || true)"
  [ -z "$left" ] || fail "$CASE: temporaries left in $1: $left"
}
# expect_status WANT GOT
expect_status() { [ "$2" = "$1" ] || fail "$CASE: exit status $2, expected $1 ($(head -c 300 "$tmp/err"))"; }
expect_message() { grep -qF -- "$1" "$tmp/err" || fail "$CASE: no '$1' in: $(head -c 300 "$tmp/err")"; }

# 1. Each libc step of the write fails (for PNG), and a failed write for each format.
for fault in write-eio fsync-eio close-eio rename-eio; do
  for ext in png jpg tif exr; do
    [ $fault != write-eio ] && [ $ext != png ] && continue
    CASE="$fault .$ext"
    d="$tmp/shim-$fault-$ext"
    mkdir -p "$d"
    old_file "$d" "out.$ext"
    SNELL_FAULT=$fault LD_PRELOAD="$shim" "$snell" render "$scene" "${small[@]}" \
      -o "$d/out.$ext" 2> "$tmp/err"
    expect_status 3 $?
    expect_message "cannot write $d/out.$ext: Input/output error"
    untouched "$d" "out.$ext"
    no_leftovers "$d"
  done
done

# 2. Short and interrupted writes: the file is still whole, byte for byte the same.
CASE="short writes"
mkdir -p "$tmp/short"
"$snell" render "$scene" "${small[@]}" -o "$tmp/short/ref.png" -o "$tmp/short/ref.exr" 2> "$tmp/err"
expect_status 0 $?
SNELL_FAULT=short-writes LD_PRELOAD="$shim" "$snell" render "$scene" "${small[@]}" \
  -o "$tmp/short/a.png" -o "$tmp/short/a.exr" 2> "$tmp/err"
expect_status 0 $?
cmp -s "$tmp/short/ref.png" "$tmp/short/a.png" || fail "$CASE: the PNG differs"
# (The EXR's header holds the render time: its pixels are compared.)
idiff -fail 0 -failpercent 0 "$tmp/short/ref.exr" "$tmp/short/a.exr" > /dev/null ||
  fail "$CASE: the EXR's pixels differ"

# 3. A signal in the write phase: the process ends by it, nothing is left.
for sig in sigterm sigint; do
  CASE="$sig while writing"
  d="$tmp/$sig"
  mkdir -p "$d"
  old_file "$d" out.png
  SNELL_FAULT=$sig LD_PRELOAD="$shim" "$snell" render "$scene" "${small[@]}" -o "$d/out.png" \
    2> "$tmp/err"
  status=$?
  want=$([ $sig = sigterm ] && echo 143 || echo 130)
  expect_status "$want" "$status"
  untouched "$d" out.png
  no_leftovers "$d"
done

# 4. A signal during the render.
for sig in TERM INT; do
  CASE="SIG$sig while rendering"
  d="$tmp/render-$sig"
  mkdir -p "$d"
  old_file "$d" out.png
  # A non-interactive shell starts background jobs with SIGINT ignored (and an
  # ignored signal cannot be reset by trap): python restores the default first.
  python3 -c 'import os, signal, sys
signal.signal(signal.SIGINT, signal.SIG_DFL)
os.execv(sys.argv[1], sys.argv[1:])' "$snell" render "$scene" --res 640x360 --spp 64 --quiet \
    -o "$d/out.png" 2> "$tmp/err" &
  pid=$!
  sleep 0.7
  kill -s "$sig" "$pid"
  wait "$pid"
  status=$?
  want=$([ $sig = TERM ] && echo 143 || echo 130)
  expect_status "$want" "$status"
  untouched "$d" out.png
  no_leftovers "$d"
done

# 5. A real full disk: a 256 KB tmpfs, filled, in a mount namespace of its own
#    (gone with the process). A later output on another disk is still written.
if [ "$(id -u)" = 0 ] && unshare -m true 2> /dev/null; then
  for ext in png jpg tif exr; do
    CASE="full disk .$ext"
    d="$tmp/full-$ext"
    mkdir -p "$d/disk" "$d/other"
    # The checks run inside the namespace, where the tmpfs is mounted.
    unshare -m --propagation private bash -c '
      set -u
      d="$1"; ext="$2"; snell="$3"; scene="$4"
      mount -t tmpfs -o size=256k snell-full "$d/disk" || exit 90
      printf "old bytes of out.%s\n" "$ext" > "$d/disk/out.$ext"
      dd if=/dev/zero of="$d/disk/fill" bs=4k 2> /dev/null
      "$snell" render "$scene" --res 200x150 --spp 1 --quiet \
        -o "$d/disk/out.$ext" -o "$d/other/later.$ext" 2> "$d/err"
      echo $? > "$d/status"
      cp "$d/disk/out.$ext" "$d/old-after"
      ls -A "$d/disk" > "$d/listing"
    ' _ "$d" "$ext" "$snell" "$scene"
    if [ "$(cat "$d/status" 2> /dev/null)" = "" ]; then
      fail "$CASE: the tmpfs could not be set up"
      continue
    fi
    cp "$d/err" "$tmp/err"
    expect_status 3 "$(cat "$d/status")"
    expect_message "cannot write $d/disk/out.$ext: No space left on device"
    [ "$(cat "$d/old-after")" = "old bytes of out.$ext" ] || fail "$CASE: the old file was changed"
    if grep -qF .snell-tmp- "$d/listing"; then fail "$CASE: a temporary was left"; fi
    [ -s "$d/other/later.$ext" ] || fail "$CASE: the later output was not written"
  done
else
  echo "skip: the full-disk cases need root and unshare -m"
fi

# 6. A symlink is written through (the link stays, its target is replaced) and an
#    existing file keeps its mode.
CASE="symlink and mode"
d="$tmp/link"
mkdir -p "$d/real"
old_file "$d/real" target.png
chmod 640 "$d/real/target.png"
ln -s real/target.png "$d/link.png"
"$snell" render "$scene" "${small[@]}" -o "$d/link.png" 2> "$tmp/err"
expect_status 0 $?
[ -L "$d/link.png" ] || fail "$CASE: the symlink was replaced"
[ "$(stat -c %a "$d/real/target.png")" = 640 ] || fail "$CASE: the mode is $(stat -c %a "$d/real/target.png")"
[ "$(head -c 4 "$d/real/target.png" | tail -c 3)" = PNG ] || fail "$CASE: the target is not the new PNG"
no_leftovers "$d"
no_leftovers "$d/real"

# 7. An output that is a file the scene reads: refused before the render (exit 2).
CASE="output is an input"
d="$tmp/inputs"
mkdir -p "$d"
cp "$src/tests/conformance/image/texels.png" "$d/texels.png"
cat > "$d/scene.scn" << 'SCN'
settings { resolution <16, 16> samples 1 }
plane { normal <0, 1, 0> material diffuse image { file "texels.png" rotate <90, 0, 0> } }
point_light { position <0, 5, 0> intensity 50 }
SCN
sum="$(md5sum < "$d/texels.png")"
"$snell" render "$d/scene.scn" --quiet -o "$d/texels.png" 2> "$tmp/err"
expect_status 2 $?
expect_message "a file this command reads"
[ "$(md5sum < "$d/texels.png")" = "$sum" ] || fail "$CASE: the image the scene reads was changed"
ln "$d/scene.scn" "$d/same-inode.png"
"$snell" render "$d/scene.scn" --quiet -o "$d/same-inode.png" 2> "$tmp/err"
expect_status 2 $?
cmp -s "$d/scene.scn" "$d/same-inode.png" || fail "$CASE: the scene was overwritten"

# 8. An image libjpeg cannot hold: an error before the render, not libjpeg's exit(1).
CASE="JPEG too wide"
d="$tmp/wide"
mkdir -p "$d"
printf 'settings { resolution <70000, 2> samples 1 }\nsphere { }\n' > "$d/wide.scn"
"$snell" render "$d/wide.scn" --stats -o "$d/w.png" -o "$d/w.jpg" 2> "$tmp/err"
expect_status 3 $?
expect_message "a JPEG holds at most 65500 pixels a side"
grep -qF "kernel:" "$tmp/err" && fail "$CASE: it rendered first"
[ -e "$d/w.png" ] && fail "$CASE: an output was written although the command failed before the render"
# libpng's limit of 1000000 a side: refused before the render too (it failed after
# it, with libpng's own lines).
CASE="PNG too tall"
printf 'settings { resolution <1, 1000001> samples 1 }\nsphere { }\n' > "$d/tall.scn"
"$snell" render "$d/tall.scn" --stats -o "$d/t.exr" -o "$d/t.png" 2> "$tmp/err"
expect_status 3 $?
expect_message "a PNG holds at most 1000000 pixels a side"
grep -qF "kernel:" "$tmp/err" && fail "$CASE: it rendered first"
grep -qF "libpng error" "$tmp/err" && fail "$CASE: libpng's own lines were printed"
[ -e "$d/t.exr" ] && fail "$CASE: an output was written although the command failed before the render"

# 9. The image helper (runtime/image_helper.hpp), the child that loads the image
#    module beside the render: killed, its encoding is an error (exit 3), not a
#    crash or a file half written; and it never outlives a killed snell.
# helper_of PID: the helper child of snell PID, once it has one (or empty).
helper_of() {
  local kids="" i
  for i in $(seq 50); do
    kids="$(cat /proc/"$1"/task/*/children 2> /dev/null | tr -s ' ' '\n' | head -1)"
    [ -n "$kids" ] && break
    sleep 0.02
  done
  echo "$kids"
}
# alive PID: running, not gone and not a zombie waiting for whoever adopted it
# (kill -0 finds those too).
alive() {
  local st
  st="$(awk '{print $3}' /proc/"$1"/stat 2> /dev/null)"
  [ -n "$st" ] && [ "$st" != Z ]
}
# waiting PID: returns once the helper PID has loaded and waits for a request
# (blocked reading its socket), or after 4 s where the kernel hides wchan. A
# fixed sleep was not enough: beside a 2-thread render on a loaded 2-core
# machine the load can take over a second.
waiting() {
  local i
  for i in $(seq 200); do
    case "$(cat /proc/"$1"/wchan 2> /dev/null)" in *unix_stream* | *sock* | *recv*) return ;; esac
    sleep 0.02
  done
}
# Killed while it loads (at once) and once it has loaded (the render takes
# 6 s alone): the one is said as a writer that could not load, the other when
# the render's image is to be encoded.
for when in loading encoding; do
  CASE="image helper killed while $when"
  d="$tmp/helper-$when"
  mkdir -p "$d"
  old_file "$d" out.png
  spp=24
  [ $when = encoding ] && spp=48
  # A folder with no server in it: the run starts a helper of its own.
  SNELL_IMAGE_SERVER_DIR="$d/servers" \
    "$snell" render "$scene" --res 640x360 --spp $spp --quiet -o "$d/out.png" 2> "$tmp/err" &
  pid=$!
  child="$(helper_of $pid)"
  if [ -z "$child" ]; then
    fail "$CASE: snell started no helper process"
  else
    [ $when = encoding ] && waiting "$child"
    kill -KILL "$child"
  fi
  wait "$pid"
  expect_status 3 $?
  if [ $when = loading ]; then
    expect_message "cannot write images: the image helper ended while loading (it was ended by signal 9)"
  else
    expect_message "cannot write $d/out.png: the image helper ended while encoding (it was ended by signal 9)"
  fi
  untouched "$d" out.png
  no_leftovers "$d"
  [ -n "$(ls -A "$d/servers" 2> /dev/null)" ] && fail "$CASE: a killed helper left a server: $(ls -A "$d/servers")"
done

CASE="snell killed: its image helper goes too"
d="$tmp/killed"
mkdir -p "$d"
SNELL_IMAGE_SERVER_DIR="$d/servers" \
  "$snell" render "$scene" --res 640x360 --spp 64 --quiet -o "$d/gone.png" 2> "$tmp/err" &
pid=$!
child="$(helper_of $pid)"
kill -KILL "$pid"
wait "$pid" 2> /dev/null
if [ -n "$child" ]; then
  for i in $(seq 50); do
    alive "$child" || break
    sleep 0.02
  done
  alive "$child" && fail "$CASE: the helper $child is still running"
else
  fail "$CASE: snell started no helper process"
fi
[ -n "$(ls -A "$d/servers" 2> /dev/null)" ] && fail "$CASE: it left a server: $(ls -A "$d/servers")"

# 10. The resident image server (runtime/image_server.hpp): the helper of a run
#     that ended stays, later runs encode through it (the same bytes), it ends when
#     idle, and a server killed leaves a name the next run takes over.
# server_pids DIR: the servers whose socket folder is DIR (by their environment).
server_pids() {
  local p
  for p in /proc/[0-9]*; do
    [ "$(cat "$p/comm" 2> /dev/null)" = snell-images ] || continue
    tr '\0' '\n' 2> /dev/null < "$p/environ" | grep -qxF "SNELL_IMAGE_SERVER_DIR=$1" &&
      echo "${p#/proc/}"
  done
}
d="$tmp/resident"
mkdir -p "$d"
# A folder of their own: a server left by a run of the cases above (alive for
# SNELL_IMAGE_SERVER_IDLE after it) would answer the "first" run below, depending
# on how fast those cases went.
export SNELL_IMAGE_SERVER_DIR="$d/servers"
small_png() { "$snell" render "$scene" "${small[@]}" --stats -o "$d/$1" 2> "$tmp/err"; }
CASE="resident server: the first run starts it"
SNELL_IMAGE_SERVER=0 "$snell" render "$scene" "${small[@]}" -o "$d/own.png" 2> "$tmp/err"
expect_status 0 $?
small_png first.png
expect_status 0 $?
expect_message "images encoded by: a helper process"
CASE="resident server: a later run encodes through it"
small_png second.png
expect_status 0 $?
expect_message "images encoded by: the resident image server"
cmp -s "$d/own.png" "$d/second.png" || fail "$CASE: its PNG differs from the in-process one"
CASE="resident server: killed, the next run starts another"
pids="$(server_pids "$SNELL_IMAGE_SERVER_DIR")"
[ "$(echo "$pids" | wc -w)" = 1 ] || fail "$CASE: $(echo "$pids" | wc -w) servers, expected 1"
[ -n "$pids" ] && kill -KILL $pids
small_png third.png
expect_status 0 $?
expect_message "images encoded by: a helper process"
small_png fourth.png
expect_status 0 $?
expect_message "images encoded by: the resident image server"
CASE="resident server: it ends when idle"
SNELL_IMAGE_SERVER_DIR="$d/idle" SNELL_IMAGE_SERVER_IDLE=0.5 "$snell" render "$scene" "${small[@]}" \
  -o "$d/idle.png" 2> "$tmp/err"
expect_status 0 $?
for i in $(seq 100); do
  [ -z "$(server_pids "$d/idle")" ] && [ -z "$(ls -A "$d/idle" 2> /dev/null)" ] && break
  sleep 0.1
done
[ -n "$(server_pids "$d/idle")" ] && fail "$CASE: still running after 10 s"
[ -n "$(ls -A "$d/idle" 2> /dev/null)" ] && fail "$CASE: its socket is left: $(ls -A "$d/idle")"

if [ "$failures" -gt 0 ]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "all fault cases passed"
