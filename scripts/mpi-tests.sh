#!/usr/bin/env bash
# Distributed rendering under mpirun on this host (README, "Distributed rendering"):
#  1. -np 2 and -np 3 (oversubscribed) give the same bytes as one process, for the image, the
#     hit and shadow buffers and the RTT map, and for every frame of a camera path; `rtt bench`
#     spread over the ranks writes a report of the same form;
#  2. a rank killed mid-render, a rank stopped (hung) past --rank-timeout, a scene file that is
#     bad on one rank only, and one whose geometry differs there each end the job with a non-zero status, a line naming the rank,
#     and no output file.
# Skips (status 0, a message) when the build has no MPI or mpirun is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
rtt=$PWD/build/rtt

if ! command -v mpirun >/dev/null || ! grep -q RTT_HAVE_MPI build/CMakeFiles/rtt.dir/flags.make 2>/dev/null; then
  echo "mpi-tests: no MPI in this build or no mpirun: skipped"
  exit 0
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
mpi=(mpirun --oversubscribe --bind-to none)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

args=(render --scene room --size 203x117 --aa 2 --threads 1 -q --light 1,2,1 --light 5,2.5,4)
# The ray counts of --stats-json, without times, thread counts and build figures.
counts='import json, sys
def keep(d):
    return {k: keep(v) if isinstance(v, dict) else v for k, v in d.items()
            if not any(w in k for w in ("second", "mrays", "thread", "kd_build", "rank"))}
print(json.dumps(keep(json.load(open(sys.argv[1]))), sort_keys=True))'
"$rtt" "${args[@]}" -o one.png --hits one.rtth --shadows one.rtts --rtt-map-primary one_map.png \
  --rtt-map-shadow one_smap.png --stats-json one.json
for np in 2 3; do
  "${mpi[@]}" -np $np "$rtt" "${args[@]}" -o np$np.png --hits np$np.rtth --shadows np$np.rtts \
    --rtt-map-primary np${np}_map.png --rtt-map-shadow np${np}_smap.png --stats-json np$np.json
  for ext in png rtth rtts; do cmp one.$ext np$np.$ext; done
  cmp one_map.png np${np}_map.png
  cmp one_smap.png np${np}_smap.png
  [ "$(/usr/bin/python3 -c "$counts" one.json)" = "$(/usr/bin/python3 -c "$counts" np$np.json)" ] ||
    { echo "mpi-tests: -np $np: the ray counts differ" >&2; exit 1; }
  echo "mpi-tests: -np $np: image, hits, shadows, both maps and ray counts identical to one process"
done

# A camera path: with at least as many frames as ranks, whole frames go to the ranks; every
# frame's outputs must equal one process's.
for i in 0 1 2 3 4; do echo "$((5 - i)).4,1.$((6 + i)),4.7,2.2,1.05,1.3,0,1,0,60"; done > path.txt
frame_args=(render --scene room --camera-path path.txt --size 96x64 --aa 2 --threads 1 -q)
"$rtt" "${frame_args[@]}" -o one_%02d.png --hits one_%02d.rtth
for np in 2 3; do
  "${mpi[@]}" -np $np "$rtt" "${frame_args[@]}" -o np${np}_%02d.png --hits np${np}_%02d.rtth
  for f in 00 01 02 03 04; do cmp one_$f.png np${np}_$f.png; cmp one_$f.rtth np${np}_$f.rtth; done
  echo "mpi-tests: -np $np: 5 frames of a camera path, distributed whole, identical to one process"
done

# rtt bench under mpirun: whole experiments on the ranks, one report of the same form (the same
# experiments in the same order, with as many measurements and tables) as one process writes.
"$rtt" bench all --quick --scenes room --out-dir one-bench --json one.json > one-bench.log
"${mpi[@]}" -np 2 "$rtt" bench all --quick --scenes room --out-dir np-bench --json np.json > np-bench.log
form='import json, sys
d = json.load(open(sys.argv[1]))
print([(e["id"], len(e["measurements"]), len(e["tables"]), len(e["files"])) for e in d["experiments"]])'
[ "$(/usr/bin/python3 -c "$form" one.json)" = "$(/usr/bin/python3 -c "$form" np.json)" ] ||
  { echo "mpi-tests: the distributed bench report differs in form" >&2; exit 1; }
grep -q "run on rank 1" np-bench.log || { echo "mpi-tests: rank 1 ran no experiment" >&2; exit 1; }
echo "mpi-tests: -np 2 rtt bench all --quick: $(grep -c 'run on rank 1' np-bench.log) experiments on rank 1, report of the same form"

# The pid of rank 1 of a job whose command line contains $1.
rank1_of() {
  local victim="" p
  for _ in $(seq 1 200); do
    for p in $(pgrep -f "$1" || true); do
      if tr '\0' '\n' < /proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1; then victim=$p; fi
    done
    [ -n "$victim" ] && break
    sleep 0.05
  done
  [ -n "$victim" ] || { echo "mpi-tests: rank 1 never started" >&2; exit 1; }
  echo "$victim"
}

# Runs a job that must fail: non-zero status, mpirun's output holding $1, no file named $2*.
expect_failure() {
  local pattern=$1 outputs=$2 status=$3
  if [ "$status" -eq 0 ]; then echo "mpi-tests: the job did not fail ($pattern)" >&2; exit 1; fi
  if ls "$outputs"* ".$outputs"* >/dev/null 2>&1; then echo "mpi-tests: a failed job left output" >&2; exit 1; fi
  grep -q "$pattern" mpirun.log || { echo "mpi-tests: no '$pattern' in:" >&2; cat mpirun.log >&2; exit 1; }
  echo "mpi-tests: exit status $status, no output; $(grep -m1 "$pattern" mpirun.log)"
}

# A rank killed mid-render.
"${mpi[@]}" -np 2 "$rtt" render --scene office --size 2048x1536 --aa 4 --threads 1 -q -o killed.png \
  --hits killed.rtth > mpirun.log 2>&1 &
launcher=$!
victim=$(rank1_of "$rtt render --scene office --size 2048x1536")
sleep 2  # loading and building: the kill falls in the middle of the job
kill -9 "$victim"
status=0
wait $launcher || status=$?
expect_failure "signal 9" killed $status

# A rank that hangs (stopped by SIGSTOP) while the others render: rank 0 gives up after
# --rank-timeout seconds and names it.
# The job is long (several seconds per rank) so that the stop falls inside it.
"${mpi[@]}" -np 2 "$rtt" render --scene room --size 2048x1536 --aa 4 --threads 1 -q -o hung.png \
  --rank-timeout 3 > mpirun.log 2>&1 &
launcher=$!
victim=$(rank1_of "$rtt render --scene room --size 2048x1536")
sleep 1
kill -STOP "$victim"
status=0
wait $launcher || status=$?
kill -CONT "$victim" 2>/dev/null || true  # a stopped process may outlive mpirun's SIGTERM
kill -9 "$victim" 2>/dev/null || true
expect_failure "rank 1 has not" hung $status

# Each rank reads scene.obj from its own folder (as on machines whose copies of a file differ):
# rank 0's holds $1, rank 1's $2; the job must stop with an error holding $3, no hang.
per_rank_scene() {
  rm -rf r0 r1 && mkdir r0 r1
  printf "$1" > r0/scene.obj
  printf "$2" > r1/scene.obj
  local status=0
  timeout 60 "${mpi[@]}" -np 2 bash -c "cd r\$OMPI_COMM_WORLD_RANK && exec '$rtt' render --mesh scene.obj \
    --size 64x48 -q -o '$work/per_rank.png'" > mpirun.log 2>&1 || status=$?
  expect_failure "$3" per_rank $status
}
triangle='v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'
# Malformed on rank 1.
per_rank_scene "$triangle" 'v 0 0 0\nf 1 2 x\n' "rank 1 of 2: scene.obj:2"
# Both load, with different geometry: the shared tree would be wrong on rank 1.
per_rank_scene "$triangle" 'v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n' "rank 1 of 2: this rank's scene is not rank 0's"
