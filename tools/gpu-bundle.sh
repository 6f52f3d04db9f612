#!/usr/bin/env bash
# Packs what tools/gpu-bench.sh needs for a GPU machine that has none of the project's
# packages (the device tool's lent machines: no package registry, another distribution):
# raystream-bench built for it (Release, no OSMesa: libOSMesa pulls in ~140 MB of LLVM that
# an NVIDIA run never loads; no tests, trackers or optical backend), jq, and every shared
# library the two load beyond the C and C++ runtimes, which the machine's own must provide
# (its NVIDIA driver needs its own libstdc++). tools/gpu-device-run.sh unpacks it there.
# The archive is written all or nothing; its MANIFEST names the commit, the libraries and
# the newest glibc symbol version they need.
set -euo pipefail
usage() {
  cat <<'EOF'
usage: tools/gpu-bundle.sh [--build DIR] [--out FILE]
  Builds raystream-bench for a GPU machine in DIR and packs it, jq and the shared libraries
  they need (all but the C and C++ runtimes) into FILE, a .tar.gz for
  tools/gpu-device-run.sh; the file's name on stdout, progress on stderr.
  --build DIR   the build folder (default: build-gpu/ in the source tree; configured
                Release with -DRS_WITH_OSMESA=OFF -DRS_BUILD_TESTS=OFF)
  --out FILE    the archive (default: .gpu/raystream-gpu.tar.gz in the source tree)
EOF
}
die() { echo "gpu-bundle: $*" >&2; exit "${code:-1}"; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-gpu
out=$root/.gpu/raystream-gpu.tar.gz
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --build|--out)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in --build) build=$2 ;; --out) out=$2 ;; esac
      shift 2 ;;
    *) code=2 die "unknown option '$1' (try --help)" ;;
  esac
done
case $out in *.tar.gz) ;; *) code=2 die "--out: '$out' does not end in .tar.gz" ;; esac
for tool in cmake jq ldd tar gzip; do
  command -v "$tool" >/dev/null || die "$tool is needed (tools/deps.sh)"
done
mkdir -p "$(dirname "$out")" 2>/dev/null && [ -w "$(dirname "$out")" ] ||
  die "cannot write to $(dirname "$out")"

mkdir -p "$build" 2>/dev/null || die "cannot make $build"
echo "gpu-bundle: building raystream-bench in $build" >&2
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DRS_WITH_OSMESA=OFF \
  -DRS_BUILD_TESTS=OFF -DRS_WITH_OPENCV=OFF -DRS_WITH_HIDAPI=OFF -DRS_WITH_LIBUSB=OFF \
  >"$build/gpu-bundle.log" 2>&1 || die "cmake configure failed (see $build/gpu-bundle.log)"
cmake --build "$build" --target raystream-bench -j "$(nproc)" >>"$build/gpu-bundle.log" 2>&1 ||
  die "build failed (see $build/gpu-bundle.log)"
bench=$build/tools/bench/raystream-bench
[ -x "$bench" ] || die "$bench was not built"

tmp="" outtmp=""
trap 'rm -rf "$tmp"; [ -z "$outtmp" ] || rm -f "$outtmp"' EXIT
tmp=$(mktemp -d)
mkdir -p "$tmp/build/tools/bench" "$tmp/bin" "$tmp/lib"
cp "$bench" "$tmp/build/tools/bench/"
cp "$(command -v jq)" "$tmp/bin/"

# The C and C++ runtimes (and the loader) stay the machine's: glibc is backward compatible,
# and a driver loaded into the process may need a newer libstdc++ than this one.
runtime='^(linux-vdso|ld-linux|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libgcc_s|libstdc\+\+)\.so'
libs=()
for exe in "$tmp/build/tools/bench/raystream-bench" "$tmp/bin/jq"; do
  missing=$(ldd "$exe" | awk '/not found/ {print $1}')
  [ -z "$missing" ] || die "$(basename "$exe") needs libraries this machine lacks: $missing"
  while read -r name path; do
    [[ $name =~ $runtime ]] && continue
    [ -f "$path" ] || continue
    cp -L "$path" "$tmp/lib/$name"
    libs+=("$name")
  done < <(ldd "$exe" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}')
done
case " ${libs[*]} " in
  *" libOSMesa"*|*" libLLVM"*) die "raystream-bench still links OSMesa/LLVM (configure $build with -DRS_WITH_OSMESA=OFF)" ;;
esac
glibc=$(for f in "$tmp"/build/tools/bench/raystream-bench "$tmp"/bin/jq "$tmp"/lib/*; do
  objdump -T "$f" 2>/dev/null | grep -o 'GLIBC_[0-9.]*' || true; done | sort -uV | tail -n 1)
{
  echo "raystream GPU bundle (tools/gpu-bundle.sh)"
  echo "source: $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
  echo "built: $(date -u '+%Y-%m-%d %H:%M UTC') on $(. /etc/os-release && echo "$PRETTY_NAME"), $(uname -m)"
  echo "needs: glibc with ${glibc:-unknown}, libstdc++ and libgcc_s from the machine"
  echo "libraries: $(printf '%s\n' "${libs[@]}" | sort -u | tr '\n' ' ')"
} >"$tmp/MANIFEST"

outtmp=$(mktemp "$out.tmp-XXXXXX") || die "cannot write $out"
tar -C "$tmp" -czf "$outtmp" . || die "cannot write $out"
mv -f "$outtmp" "$out" || die "cannot write $out"
outtmp=""
echo "gpu-bundle: $(du -h "$out" | cut -f1) with $(ls "$tmp/lib" | wc -l) libraries; $(sed -n 's/^needs: //p' "$tmp/MANIFEST")" >&2
echo "$out"
