#!/usr/bin/env bash
# The include graph of src/ (design notes section 1): a file in src/<room>/ includes only
# the public headers (hsbd/...), the headers of its own room and those of core/, the room
# every other one stands on; the run lifecycle (src/run/), which sits on top, also the
# writers of src/io/, the checkpoint interfaces of the rooms below (<room>/checkpoint.h) and
# the run directories (src/rundir/: locks, ensembles, merges), which the validation also
# uses; the run directories include the writers of src/io/ and nothing of src/run/.
# So the configuration room's schema (src/config/schema.h) is its own: every other room
# reads the configuration through hsbd/config.h. Inside each room the files form no cycle. A
# file and the header of the same name are one node (x.c, x.h -> x), so two files that call
# each other through their headers are a cycle too. Prints the offending lines or the loop.
set -u
SRC=${1:?usage: check_includes.sh path/to/src}
fail=0
for dir in "$SRC"/*/; do
    room=$(basename "$dir")
    edges=$(mktemp)
    for file in "$dir"*.c "$dir"*.h; do
        [ -e "$file" ] || continue
        node=$(basename "$file" | sed 's/\.[ch]$//')
        echo "$node $node" >>"$edges" # every file is a node, with or without includes
        while IFS= read -r inc; do
            case "$room:$inc" in
            *:hsbd/* | *:core/*) ;;
            "$room:$room"/*) ;;
            run:io/* | run:*/checkpoint.h | run:rundir/* | validate:rundir/* | rundir:io/*) ;;
            */*)
                echo "FAIL: $file includes \"$inc\": another room's internal header" >&2
                fail=1
                ;;
            esac
            case "$inc" in
            "$room"/*)
                target=$(basename "$inc" .h)
                [ "$target" = "$node" ] || echo "$node $target" >>"$edges"
                ;;
            esac
        done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$file")
    done
    # tsort prints the members of a loop and fails when the graph has one
    if ! tsort "$edges" >/dev/null 2>"$edges.err"; then
        echo "FAIL: src/$room: the includes form a cycle:" >&2
        cat "$edges.err" >&2
        fail=1
    fi
    rm -f "$edges" "$edges.err"
done
[ "$fail" = 0 ] && echo "check_includes: every room includes only core/ and itself, without cycles"
exit "$fail"
