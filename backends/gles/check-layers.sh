#!/usr/bin/env bash
# The GLES backend is a one-way stack (gles_internal.h, docs/gles.md "Call stack"): a file
# calls functions of its own layer or of the layers below, never above, and the calls
# between files form no circle. This script reads every call of an rs_gl*/rs_gles_*
# function between the folder's files, fails naming each call upwards and each circle,
# and with --diagram prints the calls as "caller -> callee" lines.
set -euo pipefail
dir=$(cd "$(dirname "$0")" && pwd)
cd "$dir"
# file:layer (1 = top). A new file must be placed here.
layers="gles_renderer.c:1
gles_shadow.c:2 gles_envmap.c:2 gles_interreflect.c:2
gles_plan.c:3 gles_frame.c:3 gles_display.c:3
gles_program.c:4 gles_prelude.c:4 gles_uniforms.c:4 gles_scene.c:4 gles_storage.c:4
gles_state.c:5 gles_alloc.c:5 gl_api.c:5"
declare -A layer def
for entry in $layers; do
	layer[${entry%%:*}]=${entry##*:}
done
status=0
for f in *.c; do
	if [ -z "${layer[$f]:-}" ]; then
		echo "check-layers: $f has no layer (add it to $0 and gles_internal.h)" >&2
		status=1
	fi
done
# Definitions: a non-static function named rs_gl* starting a line.
for f in "${!layer[@]}"; do
	while read -r name; do
		def[$name]=$f
	done < <(grep -hoE '^[a-zA-Z][^(;=]*[ *]rs_gl[a-z0-9_]*\(' "$f" | grep -oE 'rs_gl[a-z0-9_]*' || true)
done
edges=$(for f in "${!layer[@]}"; do
	grep -oE '\brs_gl[a-z0-9_]*\(' "$f" | tr -d '(' | sort -u | while read -r name; do
		g=${def[$name]:-}
		if [ -n "$g" ] && [ "$g" != "$f" ]; then
			echo "$f $g $name"
		fi
	done
done | sort)
while read -r f g name; do
	[ -n "$f" ] || continue
	if [ "${layer[$g]}" -lt "${layer[$f]}" ]; then
		echo "check-layers: $f (layer ${layer[$f]}) calls $name of $g (layer ${layer[$g]}), above it" >&2
		status=1
	fi
done <<<"$edges"
if ! cut -d' ' -f1,2 <<<"$edges" | sort -u | tsort >/dev/null 2>/tmp/check-layers.$$; then
	echo "check-layers: the calls between files form a circle:" >&2
	cat /tmp/check-layers.$$ >&2
	status=1
fi
rm -f /tmp/check-layers.$$
if [ "${1:-}" = "--diagram" ]; then
	cut -d' ' -f1,2 <<<"$edges" | sort -u | while read -r f g; do
		echo "${layer[$f]} $f -> ${layer[$g]} $g"
	done | sort -n | cut -d' ' -f2,3,5
fi
[ $status -eq 0 ] && echo "check-layers: $(wc -l <<<"$edges") calls between $(ls *.c | wc -l) files, all downwards, no circle"
exit $status
