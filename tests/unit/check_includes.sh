#!/usr/bin/env bash
# The include graph of src/ (docs/architecture.md): a file in src/<room>/ (or a folder
# inside it, such as src/run/observers/) includes only the public headers (hsbd/...), the
# headers of its own room and those of core/, the room every other one stands on; the run
# lifecycle (src/run/), which sits on top, also the writers of src/io/, the checkpoint
# interfaces of the rooms below (<room>/checkpoint.h) and the run directories (src/rundir/:
# locks, ensembles, merges), which the validation also uses; the run directories include the
# writers of src/io/ and nothing of src/run/.
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
    while IFS= read -r file; do
        node=${file#"$dir"}
        node=${node%.[ch]}
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
                target=${inc#"$room"/}
                target=${target%.h}
                [ "$target" = "$node" ] || echo "$node $target" >>"$edges"
                ;;
            esac
        done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$file")
    done < <(find "$dir" -name '*.[ch]' | sort)
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
