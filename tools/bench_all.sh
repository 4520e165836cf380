#!/usr/bin/env bash
# Regenerates the measured tables of docs/performance.md: runs the project's own binaries (daisy,
# bench_formfactors, tools/bench_formfactor_family.sh) under /usr/bin/time and rewrites each table
# between its markers <!-- bench_all:NAME --> ... <!-- /bench_all:NAME -->, stamped with the
# machine, the date, the commit and the commands. Run it on an otherwise idle machine: the
# default run takes about 5-10 minutes on 2 cores.
#
# Usage: tools/bench_all.sh BUILD_DIR [--quick] [--accuracy] [--dry-run] [--doc FILE]
#                           [--only NAME[,NAME...]] [--rounds N]
#   --quick     tiny inputs and one round, to check this script; prints the tables and writes no
#               document unless --doc is given
#   --accuracy  also the render accuracy against the path tracer (hours: references of 4,096 to
#               8,192 samples a pixel, kept with the charts and error images in BUILD_DIR/bench_all
#               for the next run); without it that table is left as it is
#   --dry-run   print the commands, run nothing, write nothing
#   --doc FILE  the document to update (default docs/performance.md; none with --quick)
#   --only      a subset of: main-job view-factors family solve gpu viewer large accuracy
#   --rounds N  rounds of each timed command (default 5 for the main job, 3 elsewhere)
# Exit status: 0 done, 1 a measurement failed (its log is printed), 2 bad usage.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

usage() { awk 'NR >= 8 && /^#/ { sub(/^# ?/, ""); print; next } NR >= 8 { exit }' "$0" >&2; exit 2; }
[[ $# -ge 1 && $1 != -* ]] || usage
build="$(cd "$1" && pwd)" || usage
shift
quick=0 accuracy=0 dry=0 doc="" docGiven=0 rounds=""
only="main-job,view-factors,family,solve,gpu,viewer,large"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) quick=1 ;;
        --accuracy) accuracy=1 ;;
        --dry-run) dry=1 ;;
        --doc) doc="$2"; docGiven=1; shift ;;
        --only) only="$2"; shift ;;
        --rounds) rounds="$2"; shift ;;
        *) echo "bench_all: unknown argument $1" >&2; usage ;;
    esac
    shift
done
[[ $accuracy == 1 && $only != *accuracy* ]] && only="$only,accuracy"
if [[ $docGiven == 0 && $quick == 0 ]]; then doc="$root/docs/performance.md"; fi
if [[ -n $doc && ! -f $doc ]]; then echo "bench_all: no document $doc" >&2; exit 2; fi
daisy="$build/daisy"
tools=("$daisy")
# Only the view-factor sections run bench_formfactors.
[[ ",$only," == *,view-factors,* || ",$only," == *,family,* ]] && tools+=("$build/bench_formfactors")
for tool in "${tools[@]}"; do
    [[ -x $tool || $dry == 1 ]] || { echo "bench_all: $tool not built" >&2; exit 2; }
done
[[ -x /usr/bin/time ]] || { echo "bench_all: /usr/bin/time missing (apt-get install time)" >&2; exit 2; }

# Inputs: the published ones, or tiny ones with --quick.
scenes="$root/assets/scenes"
family="$scenes/formfactor_family"
if [[ $quick == 1 ]]; then
    mainScene="$family/blacklight_small.gltf"
    meshArgs=(--subdivide 1)  # the automatic size would make 4,096 patches
    mainArgs=(--width 160)
    vfScenes=("$family/blacklight_small.gltf" "$family/open_small.gltf")
    familyArgs=(--small)
    gpuScenes=("$family/blacklight_small.gltf")
    viewArgs=(--width 320 --height 240)
    idleFrames=20
    posterEdit='light.reflectance=rgb(0.2,0.6,0.9)'
    viewBigScene="$scenes/cornell_box.gltf"
    viewBigArgs=(--subdivide 0.1)
    accuracyRuns=("cornell_box 0")  # 0: daisy bench --quick
    largeSizes=(5000 20000)
    largeArgs=(--max-memory 64M)  # so that the refusal is exercised too
    rounds="${rounds:-1}"
    mainRounds=$rounds
else
    mainScene="$scenes/blacklight_box.gltf"
    meshArgs=()
    mainArgs=()
    vfScenes=("$scenes/blacklight_box.gltf" "$family/blender_cornell.gltf")
    familyArgs=()
    gpuScenes=("$scenes/blacklight_box.gltf" "$family/blender_cornell.gltf")
    viewArgs=(--width 1280 --height 720)
    idleFrames=300
    posterEdit='poster_white.reflectance=rgb(0.2,0.6,0.9)'
    viewBigScene="$scenes/cornell_box.gltf"
    viewBigArgs=(--subdivide 0.03)  # 12,544 patches
    accuracyRuns=("cornell_box 4096" "colored_lights 2048" "blacklight_box 8192")
    largeSizes=(30000 250000)
    largeArgs=()
    mainRounds="${rounds:-5}"
    rounds="${rounds:-3}"
fi
wallEdit='white.reflectance=rgb(0.5,0.5,0.5)'
bigEdit='red.reflectance=rgb(0.1,0.6,0.2)'
# Mesa's lavapipe manifest: lvp_icd.json from Mesa 25, lvp_icd.<arch>.json before.
lavapipe=""
for manifest in /usr/share/vulkan/icd.d/lvp_icd.json /usr/share/vulkan/icd.d/lvp_icd.*.json; do
    [[ -z $lavapipe && -f $manifest ]] && lavapipe=$manifest
done

work="$(mktemp -d "${TMPDIR:-/tmp}/bench_all.XXXXXX")"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/tables"
cache="$work/xdg"  # XDG_CACHE_HOME of every daisy run: F's disk cache lives under it

# rel PATH: the path as the commands under the tables show it (relative to the repository).
rel() { local p="${1#"$root"/}"; echo "${p#"$PWD"/}"; }
# shown CMD...: the command as one line, paths relative, the work folder as $TMP.
shown() {
    local out="" a
    for a in "$@"; do
        a="${a//$work/\$TMP}"
        a="${a//$root\//}"
        [[ $a == *[[:space:]\'\(\)\|\;]* ]] && a="'$a'"
        out+="${out:+ }$a"
    done
    echo "$out"
}

# run NAME CMD...: runs CMD under /usr/bin/time; its output goes to $work/NAME.log and its
# wall s, user s, sys s and peak RSS KB to $work/NAME.time. With --dry-run it only prints CMD.
run() {
    local name="$1"
    shift
    echo "+ $(shown "$@")" >&2
    [[ $dry == 1 ]] && return 0
    if ! /usr/bin/time -f '%e %U %S %M' -o "$work/$name.time" "$@" >"$work/$name.log" 2>&1; then
        echo "bench_all: failed: $(shown "$@")" >&2
        tail -n 30 "$work/$name.log" >&2
        exit 1
    fi
}
# field NAME K: field K (1 wall, 2 user, 3 sys, 4 KB) of run NAME's times.
field() { tail -n 1 "$work/$1.time" | awk -v k="$2" '{print $k}'; }
# stats V...: "median (min-max)" of the values (arguments, each may hold several separated by
# spaces), or the one value; FMT is their printf format.
stats() {
    echo "$*" | tr ' ' '\n' | sort -g | awk -v fmt="${FMT:-%.2f}" '
        /[0-9]/ { v[++n] = $1 }
        END {
            if (n == 0) { print "-"; exit }
            m = n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2;
            if (n == 1 || v[1] == v[n]) printf fmt "\n", m;
            else printf fmt " (" fmt "-" fmt ")\n", m, v[1], v[n];
        }'
}
# seconds TEXT: formatDuration's "2.9 s", "16 s", "1 min 02 s" as seconds.
seconds() {
    awk -v t="$1" 'BEGIN {
        n = split(t, w, " "); s = 0;
        for (i = 1; i < n; i += 2) {
            if (w[i + 1] == "h") s += 3600 * w[i];
            else if (w[i + 1] == "min") s += 60 * w[i];
            else s += w[i];
        }
        print s }'
}
# stage LOG NAME: the seconds of stage NAME on the render's "time:" line.
stage() {
    local text
    # shellcheck disable=SC2020 # two characters to newlines
    text=$(grep -m1 '  time: ' "$1" | tr ',;' '\n\n' | sed -n "s/^ *\(time: \)\{0,1\}$2 \([0-9][0-9.]* [a-z]*\( [0-9][0-9]* s\)\{0,1\}\).*/\2/p" | head -n 1)
    [[ -n $text ]] && seconds "$text" || echo ""
}
mib() { awk -v k="$1" 'BEGIN { printf "%.0f", k / 1024 }'; }

machine() {
    local cpu cores mem
    cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
    grep -qm1 'avx512f' /proc/cpuinfo && cpu="$cpu (AVX-512)"
    cores=$(grep -c '^processor' /proc/cpuinfo)
    mem=$(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)
    echo "$cpu, $cores cores, $mem"
}
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
if [[ -n $(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null) ]]; then
    commit="$commit + local changes"
fi
# stamp COMMAND...: the lines under a table: machine, date, commit, load, the commands.
stamp() {
    local load
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    echo
    echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC') by \`tools/bench_all.sh$(
        [[ $quick == 1 ]] && echo ' --quick')\` on $(machine), commit $commit, load average" \
        "$load at the end$([[ $quick == 1 ]] && echo '; TINY INPUTS, not comparable')." \
        "Commands:"
    echo
    local c
    for c in "$@"; do echo "    $c"; done
}
wants() { [[ ",$only," == *",$1,"* ]]; }
# Tables go to $work/tables/NAME.md as they are made.
table() { cat >"$work/tables/$1.md"; }

section_main_job() {
    # vals[KIND,WHAT]: the rounds' values, space-separated; KIND cold or warm.
    local -A vals=()
    local render=("$daisy" render "$(rel "$mainScene")" -o "$work/main.png" --verbose "${meshArgs[@]}" "${mainArgs[@]}")
    local stageNames=("view factors" solve "near field" "final gather")
    local i kind st
    for ((i = 1; i <= mainRounds; i++)); do
        # Interleaved: one cold run (empty cache), then one warm run reading what it stored.
        [[ $dry == 1 ]] || rm -rf "$cache"
        run "cold$i" env XDG_CACHE_HOME="$cache" "${render[@]}"
        run "warm$i" env XDG_CACHE_HOME="$cache" "${render[@]}"
        [[ $dry == 1 ]] && continue
        for kind in cold warm; do
            vals[$kind,wall]+=" $(field "$kind$i" 1)"
            vals[$kind,cpu]+=" $(awk -v u="$(field "$kind$i" 2)" -v s="$(field "$kind$i" 3)" 'BEGIN { print u + s }')"
            vals[$kind,mib]+=" $(mib "$(field "$kind$i" 4)")"
            for st in "${stageNames[@]}"; do
                vals[$kind,$st]+=" $(stage "$work/$kind$i.log" "$st")"
            done
        done
    done
    [[ $dry == 1 ]] && return 0
    {
        echo "| run | rounds | wall, median (range) | CPU user + sys | peak RSS | view factors | solve | near field | final gather |"
        echo "|---|---|---|---|---|---|---|---|---|"
        for kind in cold warm; do
            local row
            row="| $kind cache | $mainRounds | **$(stats "${vals[$kind,wall]}") s** | $(stats "${vals[$kind,cpu]}") s | $(FMT=%.0f stats "${vals[$kind,mib]}") MiB"
            for st in "${stageNames[@]}"; do
                row+=" | $(FMT=%.1f stats "${vals[$kind,$st]}") s"
            done
            echo "$row |"
        done
        stamp "rm -rf \$TMP/xdg; XDG_CACHE_HOME=\$TMP/xdg /usr/bin/time $(shown "${render[@]}")   # cold" \
              "XDG_CACHE_HOME=\$TMP/xdg /usr/bin/time $(shown "${render[@]}")   # warm, right after" \
              "(cold and warm interleaved; stage times from the render's \"time:\" line)"
    } | table main-job
}

section_view_factors() {
    local scene i
    local repeat=3
    [[ $quick == 1 ]] && repeat=1
    for scene in "${vfScenes[@]}"; do
        local name
        name=$(basename "$scene" .gltf)
        run "vf-$name" "$build/bench_formfactors" "$(rel "$scene")" --rays 4 --repeat "$repeat"
    done
    [[ $dry == 1 ]] && return 0
    {
        echo "| scene | patches | unordered pairs | non-zeros | traced pairs | rays | pair loop (best of $repeat) | whole build |"
        echo "|---|---|---|---|---|---|---|---|"
        for scene in "${vfScenes[@]}"; do
            local name
            name=$(basename "$scene" .gltf)
            local shortName
            shortName=$(rel "$scene")
            shortName=${shortName#assets/scenes/}
            grep -E '^[a-z0-9-]+,[0-9]' "$work/vf-$name.log" | tail -n 1 | awk -F, -v name="${shortName%.gltf}" '
                function n(x,  s, r) {
                    s = sprintf("%d", x); r = "";
                    while (length(s) > 3) { r = "," substr(s, length(s) - 2) r; s = substr(s, 1, length(s) - 3) }
                    return s r
                }
                { printf "| %s | %s | %s | %s | %s | %s | **%.2f s** | %.2f s |\n",
                  name, n($7), n($8), n($17), n($13), n($16), $19, $21 }'
        done
        stamp "$(shown "$build/bench_formfactors") SCENE --rays 4 --repeat $repeat" \
              "(CSV columns 7 patches, 8 pairs, 13 traced_pairs, 16 rays, 17 nonzeros, 19 pair_s, 21 total_s)"
    } | table view-factors
}

section_family() {
    run family bash "$root/tools/bench_formfactor_family.sh" "$build" "${familyArgs[@]}"
    [[ $dry == 1 ]] && return 0
    {
        echo "| scene | off | culling always | cost model | model / best | always / off | rays (model) | facing away | clear shafts | covered |"
        echo "|---|---|---|---|---|---|---|---|---|---|"
        awk 'NR > 1 && NF == 10 { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10 }' \
            "$work/family.log"
        stamp "bash tools/bench_formfactor_family.sh $(shown "$build") ${familyArgs[*]}" \
              "(one pass; pair-loop seconds; on a loaded machine run it with --reverse too and take the best)"
    } | table family
}

section_solve() {
    local solver i
    # F from the cache: one render fills it unless the main job already did.
    if [[ $dry == 1 || ! -d $cache ]]; then
        run solve-fill env XDG_CACHE_HOME="$cache" "$daisy" solve "$(rel "$mainScene")" "${meshArgs[@]}" -q
    fi
    # Southwell takes seconds where the others take tenths: one round.
    local -A solverRounds=([gauss-seidel]=$rounds [jacobi]=$rounds [southwell]=1)
    for solver in gauss-seidel jacobi southwell; do
        for ((i = 1; i <= solverRounds[$solver]; i++)); do
            run "solve-$solver-$i" env XDG_CACHE_HOME="$cache" "$daisy" solve "$(rel "$mainScene")" "${meshArgs[@]}" --solver "$solver" --verbose
        done
    done
    [[ $dry == 1 ]] && return 0
    {
        echo "| solver | rounds | wavelengths | iterations | residual | solve time, median (range) | process wall |"
        echo "|---|---|---|---|---|---|---|"
        for solver in gauss-seidel jacobi southwell; do
            local times=() walls=() line=""
            for ((i = 1; i <= solverRounds[$solver]; i++)); do
                line=$(grep -m1 'solve: ' "$work/solve-$solver-$i.log")
                times+=("$(sed -n 's/.*residual [^,]*, \([0-9.e+-]*\) s.*/\1/p' <<<"$line")")
                walls+=("$(field "solve-$solver-$i" 1)")
            done
            local its res wl
            its=$(sed -n 's/.*solve: \([0-9]*\) iterations.*/\1/p' <<<"$line")
            res=$(sed -n 's/.*residual \([^,]*\),.*/\1/p' <<<"$line")
            wl=$(sed -n 's/.* x \([0-9]*\) wavelengths.*/\1/p' <<<"$line")
            echo "| $solver | ${solverRounds[$solver]} | $wl | $its | $res | **$(FMT=%.3f stats "${times[@]}") s** | $(stats "${walls[@]}") s |"
        done
        stamp "XDG_CACHE_HOME=\$TMP/xdg $(shown "$daisy" solve "$(rel "$mainScene")" "${meshArgs[@]}") --solver S --verbose   # F from the cache" \
              "(the time is the \"solve:\" line's)"
    } | table solve
}

section_gpu() {
    local vk=()
    [[ -f $lavapipe ]] && vk=(VK_ICD_FILENAMES="$lavapipe")
    local haveCuda=0
    if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >/dev/null 2>&1; then haveCuda=1; fi
    # Configurations: the backend and, for vulkan, how it traces shadow rays (--vulkan-rays).
    local configs=(cpu vulkan:software vulkan:query)
    [[ $haveCuda == 1 ]] && configs+=(cuda)
    local scene config backend name i
    # Interleaved rounds: each round runs every configuration on every scene once, so the
    # ratios compare runs made under the same load.
    for ((i = 1; i <= rounds; i++)); do
        for scene in "${gpuScenes[@]}"; do
            for config in "${configs[@]}"; do
                backend=${config%%:*}
                local extra=()
                [[ $config == *:* ]] && extra=(--vulkan-rays "${config#*:}")
                name="gpu-$(basename "$scene" .gltf)-${config/:/-}-$i"
                run "$name" env "${vk[@]}" XDG_CACHE_HOME="$cache" "$daisy" formfactors "$(rel "$scene")" \
                    --backend "$backend" "${extra[@]}" --no-cache --verbose -o "$work/F.mtx"
                [[ $dry == 1 ]] || rm -f "$work/F.mtx"
            done
        done
    done
    [[ $dry == 1 ]] && return 0
    {
        echo "| scene | backend | device | view factors | visibility pass | factors pass | traced pairs | non-zeros | process user | / cpu |"
        echo "|---|---|---|---|---|---|---|---|---|---|"
        for scene in "${gpuScenes[@]}"; do
            for config in "${configs[@]}"; do
                local vfs=() viss=() facs=() users=() ratios=() traced="" nnz="" device="" log cpuLog vf
                for ((i = 1; i <= rounds; i++)); do
                    name="gpu-$(basename "$scene" .gltf)-${config/:/-}-$i"
                    log="$work/$name.log"
                    vf=$(seconds "$(sed -n 's/.*view factors: .* non-zeros in \(.*\) on .*/\1/p' "$log" | head -n 1)")
                    vfs+=("$vf")
                    viss+=("$(seconds "$(sed -n "s/.*traced pairs' visibility in \([^,]*\),.*/\1/p" "$log" | head -n 1)")")
                    facs+=("$(seconds "$(sed -n 's/.*every clear pair in \([^(]*\) (.*/\1/p' "$log" | head -n 1)")")
                    users+=("$(field "$name" 2)")
                    nnz=$(sed -n 's/.*view factors: \([0-9,]*\) non-zeros in.*/\1/p' "$log" | head -n 1)
                    traced=$(sed -n 's/.*  traced: \([0-9,]*\) pairs.*/\1/p' "$log" | head -n 1)
                    device=$(grep -m1 -oiE "device '[^']*'" "$log" | sed "s/device //I; s/'//g" || true)
                    cpuLog="$work/gpu-$(basename "$scene" .gltf)-cpu-$i.log"
                    ratios+=("$(awk -v a="$vf" -v b="$(seconds "$(sed -n 's/.*view factors: .* non-zeros in \(.*\) on .*/\1/p' "$cpuLog" | head -n 1)")" 'BEGIN { if (b > 0) printf "%.2f", a / b }')")
                done
                [[ $config == cpu ]] && device="Embree, $(nproc) threads"
                local shownName=${config/:/ --vulkan-rays }
                local vis fac ratio=""
                vis=$([[ $config == cpu ]] || FMT=%.1f stats "${viss[@]}")
                fac=$([[ $config == cpu ]] || FMT=%.1f stats "${facs[@]}")
                [[ $config == cpu ]] || ratio="**$(stats "${ratios[@]}")x**"
                echo "| $(rel "$scene" | sed 's|assets/scenes/||') | $shownName | ${device:--} | **$(FMT=%.1f stats "${vfs[@]}") s** | ${vis:+$vis s} | ${fac:+$fac s} | ${traced:--} | ${nnz:--} | $(FMT=%.1f stats "${users[@]}") s | $ratio |"
            done
        done
        [[ $haveCuda == 1 ]] || echo "| | cuda | - | not run: no NVIDIA device | | | | | | |"
        stamp "$([[ ${#vk[@]} -gt 0 ]] && echo "VK_ICD_FILENAMES=$lavapipe ")/usr/bin/time $(shown "$daisy" formfactors) SCENE --backend cpu|vulkan$([[ $haveCuda == 1 ]] && echo '|cuda') [--vulkan-rays software|query] --no-cache --verbose -o \$TMP/F.mtx" \
              "($rounds interleaved rounds of every row on both scenes, median (range); the view factors from the \"view factors:\" line, the passes from vulkan's --verbose line; / cpu: the median of each round's ratio to that round's cpu run)"
    } | table gpu
}

section_viewer() {
    local xvfb=()
    if [[ -z ${DISPLAY:-} ]]; then
        if ! command -v xvfb-run >/dev/null 2>&1; then
            echo "bench_all: no DISPLAY and no xvfb-run: viewer table skipped" >&2
            return 0
        fi
        xvfb=(xvfb-run -a)
    fi
    local vk=()
    [[ -f $lavapipe ]] && vk=(VK_ICD_FILENAMES="$lavapipe")
    local scene big
    scene=$(rel "$mainScene")
    big=$(rel "$viewBigScene")
    local view=("$daisy" view "$scene" "${meshArgs[@]}" "${viewArgs[@]}" --exposure 6)
    local bigView=("$daisy" view "$big" "${viewBigArgs[@]}" "${viewArgs[@]}" --exposure 6)
    local coldCache="$work/xdg-cold"
    local loadStart
    loadStart=$(cut -d' ' -f1-3 /proc/loadavg)
    # F of both scenes in the cache first, so that every warm run below reads it.
    if [[ $dry == 1 || ! -d $cache ]]; then
        run view-fill env XDG_CACHE_HOME="$cache" "$daisy" solve "$scene" "${meshArgs[@]}" -q
    fi
    run view-fill-big env XDG_CACHE_HOME="$cache" "$daisy" solve "$big" "${viewBigArgs[@]}" -q
    local i
    for ((i = 1; i <= rounds; i++)); do
        run "view-first$i" env "${vk[@]}" XDG_CACHE_HOME="$cache" "${xvfb[@]}" /usr/bin/time -f 'launch-to-exit %e' "${view[@]}" --frames 1
        run "view-poster$i" env "${vk[@]}" XDG_CACHE_HOME="$cache" "${xvfb[@]}" "${view[@]}" --frames 3 --edit "$posterEdit"
        run "view-white$i" env "${vk[@]}" XDG_CACHE_HOME="$cache" "${xvfb[@]}" "${view[@]}" --frames 3 --edit "$wallEdit"
        run "view-big$i" env "${vk[@]}" XDG_CACHE_HOME="$cache" "${xvfb[@]}" "${bigView[@]}" --frames 3 --edit "$bigEdit"
        # An empty cache: F built after the first picture (the emitters' direct light).
        [[ $dry == 1 ]] || rm -rf "$coldCache"
        run "view-cold$i" env "${vk[@]}" XDG_CACHE_HOME="$coldCache" "${xvfb[@]}" "${view[@]}" --frames 1
    done
    run view-idle env "${vk[@]}" XDG_CACHE_HOME="$cache" "${xvfb[@]}" "${view[@]}" --frames "$idleFrames"
    [[ $dry == 1 ]] && return 0
    # vals[KIND,WHAT]: the rounds' values, space-separated; its[KIND]: the last round's iterations.
    local -A vals=() its=()
    local kind line
    for ((i = 1; i <= rounds; i++)); do
        vals[launch]+=" $(sed -n 's/^launch-to-exit \([0-9.]*\)/\1/p' "$work/view-first$i.log" | tail -n 1)"
        vals[warm]+=" $(sed -n 's/.*view: first frame \([0-9.e+]*\) ms.*/\1/p' "$work/view-first$i.log" | head -n 1)"
        vals[cold]+=" $(sed -n 's/.*view: first frame \([0-9.e+]*\) ms.*/\1/p' "$work/view-cold$i.log" | head -n 1)"
        for kind in poster white big; do
            line=$(grep -m1 'edit -> first updated frame' "$work/view-$kind$i.log" || true)
            [[ -n $line ]] || { echo "bench_all: no edit timing in view-$kind$i.log" >&2; tail -n 20 "$work/view-$kind$i.log" >&2; exit 1; }
            vals[$kind,first]+=" $(sed -n 's/.*first updated frame \([0-9.e+]*\) ms.*/\1/p' <<<"$line")"
            vals[$kind,cpu]+=" $(sed -n 's/.* with \([0-9.e+]*\) ms of process CPU.*/\1/p' <<<"$line")"
            vals[$kind,conv]+=" $(sed -n 's/.*converged frame \([0-9.e+]*\) ms.*/\1/p' <<<"$line")"
            its[$kind]=$(sed -n 's/.*; \([0-9]*\) iterations.*/\1/p' <<<"$line")
        done
    done
    local idle frame peak size patches bigPatches
    idle=$(grep -m1 'mean frame time' "$work/view-idle.log")
    frame=$(sed -n 's/.*mean frame time \([0-9.e+]*\) ms.*/\1/p' <<<"$idle")
    size=$(sed -n 's/.* ms at \([0-9]* x [0-9]*\);.*/\1/p' <<<"$idle")
    peak=$(sed -n 's/.*peak memory \(.*\)$/\1/p' <<<"$idle")
    patches=$(sed -n 's/.* \([0-9,]*\) patches x .*/\1/p' "$work/view-poster1.log" | head -n 1)
    bigPatches=$(sed -n 's/.* \([0-9,]*\) patches x .*/\1/p' "$work/view-big1.log" | head -n 1)
    ms() { FMT=%.0f stats ${vals[$1]}; }
    {
        echo "| measurement | value |"
        echo "|---|---|"
        echo "| launch to the first frame and exit, F cached (process wall, median of $rounds) | **$(stats ${vals[launch]}) s** |"
        echo "| command to the first frame, warm (F and B cached: the converged solution) | **$(ms warm) ms** |"
        echo "| command to the first frame, cold (empty cache: the emitters' direct light) | **$(ms cold) ms** |"
        echo "| edit one poster: first updated frame | **$(ms poster,first) ms** |"
        echo "| edit one poster: process CPU from the edit to that frame drawn | **$(ms poster,cpu) ms** |"
        echo "| edit one poster: converged frame (${its[poster]} iterations) | **$(ms poster,conv) ms** |"
        echo "| edit the walls and ceiling: first updated frame | **$(ms white,first) ms** |"
        echo "| edit the walls and ceiling: process CPU from the edit to that frame drawn | **$(ms white,cpu) ms** |"
        echo "| edit the walls and ceiling: converged frame (${its[white]} iterations) | **$(ms white,conv) ms** |"
        echo "| $(basename "$big") ($bigPatches patches), edit the red wall: first updated frame | **$(ms big,first) ms** |"
        echo "| $(basename "$big") ($bigPatches patches), edit the red wall: process CPU from the edit to that frame drawn | **$(ms big,cpu) ms** |"
        echo "| $(basename "$big") ($bigPatches patches), edit the red wall: converged frame (${its[big]} iterations) | **$(ms big,conv) ms** |"
        echo "| frame time, idle, $idleFrames frames at $size | **$frame ms** |"
        echo "| peak memory (idle run) | $peak |"
        stamp "XDG_CACHE_HOME=\$TMP/xdg ${xvfb[*]} /usr/bin/time $(shown "${view[@]}") --frames 1" \
              "XDG_CACHE_HOME=\$TMP/xdg ${xvfb[*]} $(shown "${view[@]}") --frames 3 --edit '$posterEdit'" \
              "XDG_CACHE_HOME=\$TMP/xdg ${xvfb[*]} $(shown "${view[@]}") --frames 3 --edit '$wallEdit'" \
              "XDG_CACHE_HOME=\$TMP/xdg ${xvfb[*]} $(shown "${bigView[@]}") --frames 3 --edit '$bigEdit'" \
              "XDG_CACHE_HOME=\$TMP/xdg-cold ${xvfb[*]} $(shown "${view[@]}") --frames 1   # after rm -rf \$TMP/xdg-cold" \
              "XDG_CACHE_HOME=\$TMP/xdg ${xvfb[*]} $(shown "${view[@]}") --frames $idleFrames" \
              "(the first five interleaved, $rounds times, median (range); ${vk[*]:-the default Vulkan driver}; $scene has $patches patches; load average $loadStart at the start)"
    } | table viewer
}

section_accuracy() {
    # Kept beside the build: daisy bench stores each reference beside its CSV and reads it back
    # on the next run with the same settings, and writes the charts and error images there.
    local keep="$build/bench_all"
    mkdir -p "$keep"
    local entry
    for entry in "${accuracyRuns[@]}"; do
        local name=${entry% *} spp=${entry#* }
        local args=(--reference-spp "$spp")
        [[ $spp == 0 ]] && args=(--quick)
        run "acc-$name" env XDG_CACHE_HOME="$cache" "$daisy" bench "$(rel "$scenes/$name.gltf")" "${args[@]}" -o "$keep/bench-path-$name.csv"
    done
    [[ $dry == 1 ]] && return 0
    {
        echo "| scene | reference | its noise | rms Y | raw | mean CIEDE2000 | render time | path tracer to 2% | measured |"
        echo "|---|---|---|---|---|---|---|---|---|"
        for entry in "${accuracyRuns[@]}"; do
            local name=${entry% *} spp=${entry#* }
            local csv="$keep/bench-path-$name.csv" noise to2
            noise=$(sed -n 's/.*reference noise \([0-9.e+-]*\).*/\1/p' "$csv" | head -n 1)
            to2=$(sed -n 's/.*the path tracer reaches 2% in \([0-9.e+]*\) s.*/\1/p' "$work/acc-$name.log" | head -n 1)
            # The default render's row: the automatic size, gather near, 16 samples at edges.
            awk -F, -v name="$name" -v spp="$spp" -v noise="$noise" -v to2="$to2" -v day="$(date -u +%Y-%m-%d)" '
                $1 == "radiosity" && $2 ~ /^"auto, gather near, 1 spp \(16 at edges\)"$/ && !done {
                    printf "| %s | %s spp | %.2f%% | **%.2f%%** | %.2f%% | %.3f | %.1f s | %.0f s | %s |\n",
                           name, spp == 0 ? "--quick" : spp, 100 * noise, 100 * $5, 100 * $6, $8, $3, to2, day;
                    done = 1
                }' "$csv"
        done
        stamp "$(shown "$daisy") bench assets/scenes/SCENE.gltf --reference-spp N -o $(shown "$keep")/bench-path-SCENE.csv" \
              "(the row of the default render: automatic patch size, --gather near, 1 spp, 16 at edges; 256 x 256)"
    } | table accuracy
}

section_large() {
    # The large interior (tools/make_large_interior.py), generated into BUILD_DIR/scenes (too
    # large to commit), at each size and as Blender's own export of the largest (when blender is
    # installed): load and estimate with `daisy info`, then the all-pairs matrix where info says
    # --max-memory refuses it, which must be a clean refusal (exit status 2, one line). The
    # matrix is named: `auto` would take the hierarchical links on these scenes.
    local dir="$build/scenes" n scene name
    local scenes=()
    for n in "${largeSizes[@]}"; do
        scene="$dir/large_interior_$n.gltf"
        run "large-gen-$n" python3 "$root/tools/make_large_interior.py" --triangles "$n" -o "$scene"
        scenes+=("$scene")
    done
    local blender=""
    if command -v blender >/dev/null 2>&1; then
        blender="$dir/large_interior_${largeSizes[-1]}_blender.glb"
        run large-blender blender --background --factory-startup --python \
            "$root/tools/blender_reexport.py" -- "${scenes[-1]}" "$blender"
        scenes+=("$blender")
    fi
    [[ $dry == 1 ]] && return 0
    local -A verdict=()
    for scene in "${scenes[@]}"; do
        name=$(basename "${scene%.*}")
        run "large-info-$name" env XDG_CACHE_HOME="$cache" "$daisy" info "$scene" --transport matrix "${largeArgs[@]}"
        verdict[$name]="fits under --max-memory: not built here (all pairs)"
        grep -q 'would be refused' "$work/large-info-$name.log" || continue
        local status=0
        echo "+ $(shown "$daisy" formfactors "$scene" "${largeArgs[@]}") --no-cache -o \$TMP/F.mtx" >&2
        /usr/bin/time -f '%e %U %S %M' -o "$work/large-f-$name.time" env XDG_CACHE_HOME="$cache" \
            "$daisy" formfactors "$scene" "${largeArgs[@]}" --no-cache -o "$work/F.mtx" \
            >"$work/large-f-$name.log" 2>&1 || status=$?
        if [[ $status != 2 || -e $work/F.mtx ]] || ! grep -q 'more than --max-memory' "$work/large-f-$name.log" \
            || [[ $(grep -c '^error: ' "$work/large-f-$name.log") != 1 ]]; then
            echo "bench_all: the all-pairs build of $(rel "$scene") was not refused cleanly (status $status)" >&2
            tail -n 30 "$work/large-f-$name.log" >&2
            exit 1
        fi
        verdict[$name]="**refused** in $(field "large-f-$name" 1) s (status 2): $(sed -n 's/.*needs about \([^,]*\) for .*, more than \(--max-memory [^;]*\);.*/\1, \2/p' "$work/large-f-$name.log")"
        # daisy bench reports the refusal as a row and keeps the path tracer's rows.
        run "large-bench-$name" env XDG_CACHE_HOME="$cache" "$daisy" bench "$scene" --transport matrix --quick \
            "${largeArgs[@]}" -o "$work/large-bench-$name.csv"
        grep -q '^refused,' "$work/large-bench-$name.csv" || {
            echo "bench_all: daisy bench $(rel "$scene") --quick has no refused row" >&2
            exit 1
        }
        verdict[$name]+="; \`daisy bench --quick\`: $(grep -c '^path,' "$work/large-bench-$name.csv") path rows and a refused row in $(field "large-bench-$name" 1) s (status 0)"
    done
    {
        echo "| scene | triangles | patches | \`daisy info\` wall | peak RSS | all-pairs F (info's estimate) | all-pairs build |"
        echo "|---|---|---|---|---|---|---|"
        for scene in "${scenes[@]}"; do
            name=$(basename "${scene%.*}")
            local log="$work/large-info-$name.log"
            echo "| $name | $(awk '$1 == "triangles" { print $2 }' "$log") | $(sed -n 's/^patches *\([0-9,]*\).*/\1/p' "$log") | **$(field "large-info-$name" 1) s** | $(mib "$(field "large-info-$name" 4)") MiB | $(sed -n 's/^matrix *~\([0-9,]*\) non-zeros.*, \([^,]*\) as CSR$/\1 non-zeros, \2/p' "$log") | ${verdict[$name]} |"
        done
        [[ -n $blender ]] || echo "| (Blender's export) | | | | | not run: no blender (Debian package blender) | |"
        stamp "python3 tools/make_large_interior.py --triangles N -o $(shown "$dir")/large_interior_N.gltf" \
              "$([[ -n $blender ]] && echo "blender --background --factory-startup --python tools/blender_reexport.py -- $(shown "${scenes[-2]}" "$blender")")" \
              "XDG_CACHE_HOME=\$TMP/xdg /usr/bin/time $(shown "$daisy" info) SCENE${largeArgs[*]:+ ${largeArgs[*]}}" \
              "XDG_CACHE_HOME=\$TMP/xdg /usr/bin/time $(shown "$daisy" formfactors) SCENE${largeArgs[*]:+ ${largeArgs[*]}} --no-cache -o \$TMP/F.mtx   # where info says it would be refused" \
              "XDG_CACHE_HOME=\$TMP/xdg /usr/bin/time $(shown "$daisy" bench) SCENE --quick${largeArgs[*]:+ ${largeArgs[*]}} -o \$TMP/large-bench-SCENE.csv   # there too"
    } | table large
}

# replace DOC: puts each table of $work/tables into DOC between its markers; every marker pair
# must exist exactly once.
replace() {
    python3 - "$1" "$work/tables" <<'EOF'
import pathlib, re, sys
doc = pathlib.Path(sys.argv[1])
text = doc.read_text()
for table in sorted(pathlib.Path(sys.argv[2]).glob("*.md")):
    name = table.stem
    begin, end = f"<!-- bench_all:{name} -->", f"<!-- /bench_all:{name} -->"
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        sys.exit(f"bench_all: {doc}: needs exactly one {begin} ... {end}")
    body = table.read_text().rstrip("\n")
    text = re.sub(re.escape(begin) + r".*?" + re.escape(end),
                  lambda m: f"{begin}\n{body}\n{end}", text, flags=re.S)
    print(f"bench_all: {doc}: replaced {name}", file=sys.stderr)
doc.write_text(text)
EOF
}

echo "bench_all: $(machine); load average $(cut -d' ' -f1-3 /proc/loadavg); build $build" >&2
for section in main-job view-factors family solve gpu viewer large accuracy; do
    wants "$section" || continue
    [[ $section == accuracy && $accuracy == 0 ]] && continue
    echo "bench_all: $section" >&2
    "section_${section//-/_}"
done
[[ $dry == 1 ]] && exit 0
for t in "$work"/tables/*.md; do
    [[ -f $t ]] || continue
    echo
    echo "<!-- $(basename "$t" .md) -->"
    cat "$t"
done
if [[ -n $doc ]]; then replace "$doc"; fi
