#!/usr/bin/env bash
# Usage: install_data.sh BUILD_DIR WORK_DIR. Installs the build to a prefix under WORK_DIR
# and checks that the installed tools find the installed data (share/raystream/cow.obj)
# from the prefix they run from, ahead of the source tree, wherever the prefix is moved;
# and that RS_DATA_DIR, when set, is the one place looked in. Prints "N passed, N failed".
set -u
build=$1
work=$2
rm -rf "$work"
mkdir -p "$work/run"
passed=0
failed=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
bad() { failed=$((failed + 1)); echo "FAILED: $1"; }
unset RS_DATA_DIR

prefix=$work/prefix
if ! cmake --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1; then
  echo "FAILED: install: $(tail -5 "$work/install.log")"
  exit 1
fi
cd "$work/run" || exit 1

# triangles PREFIX SCENE: the triangle count the installed raystream-render reports.
triangles() {
  rm -f s.json
  "$1/bin/raystream-render" --scene "$2" --backend cpu --size 8x8 --passes 1 --out c.png \
    --stats s.json >stdout.txt 2>stderr.txt || return 1
  sed -n 's/.*"triangles":[[:space:]]*\([0-9]*\).*/\1/p' s.json
}

if [ "$(triangles "$prefix" cow1)" = 5837 ]; then ok "installed render --scene cow1"
else bad "installed render --scene cow1: $(cat stderr.txt)"; fi

# A one-triangle cow.obj in the install: it is the one read (the source tree's has 5,804).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$prefix/share/raystream/cow.obj"
if [ "$(triangles "$prefix" cow1)" = 34 ]; then ok "the install's data comes before the source tree"
else bad "install data not used: $(grep -o '"triangles":[^,]*' s.json) $(cat stderr.txt)"; fi

# The prefix moved elsewhere: still its own data.
mv "$prefix" "$work/moved"
if [ "$(triangles "$work/moved" cow2)" = 35 ]; then ok "a moved prefix finds its data"
else bad "moved prefix: $(cat stderr.txt)"; fi
if "$work/moved/bin/raystream-scene" --scene cow1 --info >info.txt 2>stderr.txt &&
   grep -qx 'triangles: 34' info.txt; then ok "installed raystream-scene finds it too"
else bad "installed raystream-scene: $(cat stderr.txt) $(grep triangles info.txt)"; fi

# RS_DATA_DIR set: the only place; a folder without the model is an error naming it.
mkdir -p own
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 0 0 1\nf 1 2 4\n' >own/cow.obj
if [ "$(RS_DATA_DIR=$PWD/own triangles "$work/moved" cow1)" = 35 ]; then ok "RS_DATA_DIR first"
else bad "RS_DATA_DIR ignored: $(cat stderr.txt)"; fi
if RS_DATA_DIR=$PWD/empty "$work/moved/bin/raystream-render" --scene cow1 --backend cpu \
     --size 8x8 >stdout.txt 2>stderr.txt; then bad "RS_DATA_DIR without the model rendered"
elif grep -q "cow.obj not found in RS_DATA_DIR" stderr.txt && [ "$(wc -l <stderr.txt)" -eq 1 ]; then
  ok "RS_DATA_DIR without the model is one line naming it"
else bad "RS_DATA_DIR without the model: $(cat stderr.txt)"; fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
