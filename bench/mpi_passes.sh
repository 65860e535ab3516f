#!/usr/bin/env bash
# The passes besides the build that MPI splits (issue 31): `matlas zonal` (a database's files and
# a model), `matlas basis` (the previews' image basis and a GI basis) and `matlas evaluate`, each
# run three ways in the same run: one process on every core, one process on one thread
# (MATLAS_THREADS=1), and P ranks of one thread each (`mpirun -np P`): the last two give the
# split's scaling, what a cluster node per rank would see. Wall times (launch included), and every
# split output compared with the single process's (cmp; the evaluation's CSVs without the fits'
# seconds column).
#   bench/mpi_passes.sh DB MODEL [P] [EVAL_DB]
#     DB: a folder of MERL files (zonal); MODEL: a model of it (zonal, bases); EVAL_DB: the folder
#     evaluated (default DB), with --materials 8 --dims 2,5.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
db="$1"
model="$2"
ranks="${3:-2}"
eval_db="${4:-$db}"
exe="$repo/build/matlas"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cat "$db"/* "$model" > /dev/null  # warm the page cache
now() { date +%s.%N; }

# run NAME KIND ARGS...: KIND all (every core), one (one thread), mpi (P ranks of one thread);
# the output path is the word OUT in ARGS, replaced by $out/NAME.KIND.
run() {
  local name="$1" kind="$2"
  shift 2
  local args=()
  for a in "$@"; do args+=("${a//OUT/$out/$name.$kind}"); done
  local t0 t1
  t0=$(now)
  case "$kind" in
    all) "$exe" "${args[@]}" > "$out/$name.$kind.log" 2>&1 ;;
    one) MATLAS_THREADS=1 "$exe" "${args[@]}" > "$out/$name.$kind.log" 2>&1 ;;
    mpi) MATLAS_THREADS=1 mpirun -np "$ranks" --oversubscribe -x MATLAS_THREADS "$exe" "${args[@]}" \
           > "$out/$name.$kind.log" 2>&1 ;;
  esac
  t1=$(now)
  echo "$t1 - $t0" | bc -l
}

same() {  # same NAME: the split output against the one-thread one
  local a="$out/$1.one" b="$out/$1.mpi"
  if [[ -d "$a" ]]; then
    for f in configs loo paths material_distances; do
      if [[ "$f" == configs ]]; then
        cmp -s <(cut -d, -f1-13 "$a/$f.csv") <(cut -d, -f1-13 "$b/$f.csv") || { echo "differs ($f.csv)"; return; }
      else
        cmp -s "$a/$f.csv" "$b/$f.csv" || { echo "differs ($f.csv)"; return; }
      fi
    done
    echo "the same CSVs"
  else
    cmp -s "$a" "$b" && echo "the same bytes" || echo "differs"
  fi
}

printf '%-34s %10s %10s %10s %8s  %s\n' pass "all cores" "1 thread" "$ranks ranks" speedup "split output vs one process"
bench() {
  local name="$1"
  shift
  local all one mpi
  all=$(run "$name" all "$@")
  one=$(run "$name" one "$@")
  mpi=$(run "$name" mpi "$@")
  printf '%-34s %9.2fs %9.2fs %9.2fs %7.2fx  %s\n' "$name" "$all" "$one" "$mpi" "$(echo "$one / $mpi" | bc -l)" "$(same "$name")"
}
bench "zonal DB" zonal "$db" -o OUT
bench "zonal MODEL" zonal "$model" -o OUT
bench "basis MODEL (512x512, 64 spp)" basis "$model" -o OUT --precision f32
bench "basis MODEL --scene floor (256x192)" basis "$model" --scene floor -o OUT --width 256 --height 192 --spp 16
bench "evaluate EVAL_DB" evaluate "$eval_db" -o OUT --no-checks --quiet --materials 8 --dims 2,5
