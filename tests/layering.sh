#!/bin/sh
# The layering of sdk/: each folder may include headers only from the folders below it in the
# pipeline (format -> synthesis -> anatomy, measure -> semantics -> export, fitting -> registration, -> runtime -> capi; the
# offline tools (scan files read and registered into records, training, then learning from registrations)
# and the command line above). The build links the stages the same way
# (sdk/CMakeLists.txt); this catches an #include that reaches up before a link error would.
# The command line reaches the C API's internals only through capi/cpp_access.hpp; the offline C API
# through it and the C API's own plumbing (guard.hpp, registration_report.hpp).
# usage: layering.sh SDK_DIR
set -u
sdk=$1
runtime="common sscape_format synthesis anatomy measure semantics fitting registration export runtime"
allowed() {  # allowed FOLDER: the folders its files may include from
    case $1 in
        common) echo "" ;;
        synthesis) echo "common sscape_format" ;;
        anatomy|measure) echo "common sscape_format synthesis" ;;
        export) echo "common sscape_format synthesis measure semantics" ;;  # morph targets of the sliders
        semantics) echo "common sscape_format synthesis measure" ;;
        fitting) echo "common sscape_format synthesis anatomy" ;;
        registration) echo "common sscape_format synthesis anatomy measure fitting" ;;
        runtime) echo "common sscape_format synthesis anatomy measure semantics" ;;
        capi) echo "$runtime" ;;
        io) echo "common" ;;
        render) echo "common sscape_format synthesis anatomy measure fitting" ;;
        simulation) echo "common sscape_format synthesis anatomy fitting registration" ;;
        # Test fixtures: procedural models, and (with the training tools) a simulated scan collection.
        testing) echo "common sscape_format synthesis anatomy measure fitting registration export io simulation scan_files training" ;;
        scan_files) echo "common sscape_format synthesis anatomy measure fitting registration export io render" ;;
        training) echo "$runtime render makehuman" ;;
        learning) echo "$runtime training render scan_files" ;;
        capi_offline) echo "$runtime capi io render simulation scan_files training learning" ;;
        cli) echo "$runtime capi render simulation io testing scan_files training learning" ;;
        *) echo "?" ;;
    esac
}
fails=0
for dir in "$sdk"/*/; do
    folder=$(basename "$dir")
    ok=$(allowed "$folder")
    if [ "$ok" = "?" ]; then echo "FAIL: sdk/$folder is not in the layering table of tests/layering.sh"; fails=1; continue; fi
    for used in $(grep -rhoE '^#include "[a-z_]+/' "$dir" | sed -E 's/#include "//; s/\///' | sort -u); do
        [ "$used" = "$folder" ] && continue
        case " $ok " in *" $used "*) ;; *) echo "FAIL: sdk/$folder includes $used/ (allowed: ${ok:-nothing})"; fails=1 ;; esac
    done
done
# The command line: of capi/, only the documented bridge.
bad=$(grep -rhoE '^#include "capi/[a-z_.]+"' "$sdk/cli" | grep -v '"capi/cpp_access.hpp"' | sort -u)
[ -z "$bad" ] || { echo "FAIL: sdk/cli includes C API internals: $bad"; fails=1; }
# The offline C API: the bridge, the exception barrier and argument checks, the registration report.
bad=$(grep -rhoE '^#include "capi/[a-z_.]+"' "$sdk/capi_offline" | grep -vE '"capi/(cpp_access|guard|registration_report).hpp"' | sort -u)
[ -z "$bad" ] || { echo "FAIL: sdk/capi_offline includes C API internals: $bad"; fails=1; }
[ "$fails" -eq 0 ] && echo "layering kept"
