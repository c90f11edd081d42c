#!/usr/bin/env bash
# Issue 7's compose test (make compose-test): runs the docker-compose farm for real.
#
#  1. starts a Docker engine if none answers (installing docker.io, docker-compose and
#     debootstrap if they are missing), builds the images (deploy/build-images.sh);
#  2. brings up Redis, the object store (SeaweedFS), two coordinator replicas, dashboard and
#     2 workers under a unique project name, with random tokens and keys and free host
#     ports; the host CLI is given both replicas;
#  3. submits the Cornell box (at 128x128) from the host with build/bin/farm, waits, fetches
#     the EXR and PNG and checks both are byte-identical to `farm render` of the same scene;
#     checks a coordinator wrote no file to its own disk, replaces its container with a
#     new one and fetches the same bytes again (blobs in the object store, state in Redis);
#  4. submits a longer job (256x256, 4 samples), kills one worker container while tiles are
#     rendering, checks the job still succeeds and is byte-identical too;
#  5. submits it again and kills a coordinator container (SIGKILL) while tiles are
#     rendering: the other replica finishes the job, byte-identical too;
#  6. tears everything down (docker-compose down -v) on success and on failure.
set -euo pipefail
deploy="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$deploy/.." && pwd)"
bin="${FARM_BIN_DIR:-$root/build/bin}"
export PATH="$PATH:/usr/local/go/bin"

t_start=$EPOCHREALTIME
t_step=$EPOCHREALTIME
elapsed() { awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1fs", b - a }'; }
step() { echo "compose-test: $* ($(elapsed "$t_step"))"; t_step=$EPOCHREALTIME; }
fail() { echo "compose-test: FAIL: $*" >&2; exit 1; }

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

# 1. A Docker engine and docker-compose.
missing=()
command -v docker >/dev/null || missing+=(docker.io)
command -v dockerd >/dev/null || missing+=(docker.io)
command -v docker-compose >/dev/null || docker compose version >/dev/null 2>&1 || missing+=(docker-compose)
command -v debootstrap >/dev/null || missing+=(debootstrap)
if [ ${#missing[@]} -gt 0 ]; then
  echo "compose-test: installing ${missing[*]}"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi
if command -v docker-compose >/dev/null; then compose=(docker-compose); else compose=(docker compose); fi

work=$(mktemp -d /tmp/farm-compose-test.XXXXXX)
dockerd_pid=""
project="farmtest$$$RANDOM"
env_file="$work/farm.env"
up=""

dc() { "${compose[@]}" --env-file "$env_file" -p "$project" -f "$deploy/compose.yaml" "$@"; }

cleanup() {
  status=$?
  set +e
  if [ -n "$up" ]; then
    if [ "$status" -ne 0 ]; then
      echo "compose-test: logs of the failed run (last 40 lines a service):" >&2
      dc logs --no-color --tail=40 >&2
    fi
    t=$EPOCHREALTIME
    dc down -v --remove-orphans -t 10 >/dev/null 2>&1
    echo "compose-test: down -v ($(elapsed "$t"))"
  fi
  if [ -n "$dockerd_pid" ]; then
    kill "$dockerd_pid" 2>/dev/null && wait "$dockerd_pid" 2>/dev/null
    echo "compose-test: stopped the dockerd this test started"
  fi
  rm -rf "$work"
  echo "compose-test: $([ "$status" -eq 0 ] && echo PASS || echo FAIL) in $(elapsed "$t_start")"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if ! docker info >/dev/null 2>&1; then
  $sudo dockerd >"$work/dockerd.log" 2>&1 &
  dockerd_pid=$!
  for _ in $(seq 120); do docker info >/dev/null 2>&1 && break; sleep 0.5; done
  docker info >/dev/null 2>&1 || { cat "$work/dockerd.log" >&2; fail "dockerd did not start"; }
  step "started dockerd"
fi

# 2. Binaries on the host (the reference render and the CLI), then the images.
[ -x "$bin/farm" ] && [ -x "$bin/farm-worker" ] || fail "no $bin/farm or farm-worker: run make build"
"$root/deploy/build-images.sh"
step "images built"

# Random tokens, free host ports, a short lease so that a killed worker's task is
# requeued quickly.
rand_hex() { od -An -tx1 -N24 /dev/urandom | tr -d ' \n'; }
free_port() {
  local p
  while :; do
    p=$((20000 + RANDOM % 20000))
    (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { echo "$p"; return; }
  done
}
client_token=$(rand_hex)
coord_port=$(free_port)
coord_b_port=$(free_port)
metrics_b_port=$(free_port)
cat >"$env_file" <<ENV
FARM_CLIENT_TOKEN=$client_token
FARM_WORKER_TOKEN=$(rand_hex)
FARM_S3_ACCESS_KEY=$(rand_hex)
FARM_S3_SECRET_KEY=$(rand_hex)
FARM_BIND=127.0.0.1
FARM_COORDINATOR_PORT=$coord_port
FARM_COORDINATOR_B_PORT=$coord_b_port
FARM_METRICS_B_PORT=$metrics_b_port
FARM_DASHBOARD_PORT=$(free_port)
FARM_METRICS_PORT=$(free_port)
FARM_WORKERS=2
FARM_WORKER_THREADS=1
FARM_LEASE_DURATION=5s
FARM_IMAGE_TAG=${FARM_IMAGE_TAG:-local}
ENV
. "$env_file"

# wait_healthy: every container of the project reports healthy within 60 s.
wait_healthy() {
  local unhealthy
  for _ in $(seq 60); do
    unhealthy=$(docker ps --filter "label=com.docker.compose.project=$project" \
      --format '{{.Names}} {{.Status}}' | grep -v '(healthy)' || true)
    [ -z "$unhealthy" ] && return
    sleep 1
  done
  fail "not healthy after 60 s: $unhealthy"
}
up=1
dc up -d --scale worker=2 >"$work/up.log" 2>&1 || { cat "$work/up.log" >&2; fail "docker-compose up"; }
wait_healthy
workers=$(dc ps -q worker | wc -l)
[ "$workers" -eq 2 ] || fail "expected 2 worker containers, got $workers"
coordinators=$(dc ps -q coordinator-a coordinator-b | wc -l)
[ "$coordinators" -eq 2 ] || fail "expected 2 coordinator containers, got $coordinators"
step "farm up and healthy: redis, object store, $coordinators coordinators, dashboard, $workers workers (project $project)"

# The host CLI is given both replicas: its calls go on through one if the other goes.
export FARM_TOKEN="$client_token" FARM_COORDINATOR="127.0.0.1:$coord_port,127.0.0.1:$coord_b_port"
# leases_granted PORT: the sum of farm_leases_granted_total on that metrics port. Reads the
# whole answer before matching: with pipefail, grep -q closing the pipe early would fail
# curl with SIGPIPE on a large answer.
leases_granted() {
  curl -fsS "http://127.0.0.1:$1/metrics" | awk '/^farm_leases_granted_total/ { n += $2 } END { print n + 0 }'
}
for port in "$FARM_METRICS_PORT" "$FARM_METRICS_B_PORT"; do
  metrics=$(curl -fsS "http://127.0.0.1:$port/metrics" || true)
  grep -q '^farm_jobs_submitted_total' <<<"$metrics" || fail "no farm metrics on 127.0.0.1:$port"
done
curl -fsS -o /dev/null "http://127.0.0.1:$FARM_DASHBOARD_PORT/" || fail "no dashboard on :$FARM_DASHBOARD_PORT"

# scene NAME WIDTH SPP: a copy of the Cornell box at WIDTHxWIDTH in $work/NAME/.
scene() {
  mkdir -p "$work/$1"
  jq --argjson w "$2" --argjson s "$3" \
    '.film.width = $w | .film.height = $w | .sampling.samplesPerPixel = $s' \
    "$root/scenes/cornell-box.json" >"$work/$1/cornell-box.json"
  echo "$work/$1/cornell-box.json"
}
# without_render_time EXR: the file but for the value of its renderTime attribute (8 bytes
# after the name, the type "double" and the size: 22 bytes from the name's start), the
# seconds the job took and the one part that differs between two renders of a scene.
without_render_time() {
  local at
  at=$(LC_ALL=C grep -obUaF -m1 'renderTime' "$1" | head -n1 | cut -d: -f1)
  [ -n "$at" ] || fail "$1 has no renderTime attribute"
  head -c $((at + 22)) "$1"
  tail -c +$((at + 31)) "$1"
}
# same DIR_A DIR_B: the PNG is byte-identical, and so is the EXR but for its render time.
same() {
  cmp <(without_render_time "$1/cornell-box.exr") <(without_render_time "$2/cornell-box.exr") ||
    fail "$1/cornell-box.exr differs from $2/cornell-box.exr (beyond its renderTime)"
  cmp "$1/cornell-box.png" "$2/cornell-box.png" ||
    fail "$1/cornell-box.png differs from $2/cornell-box.png"
  echo "compose-test:   byte-identical: cornell-box.exr but its renderTime $(without_render_time "$1/cornell-box.exr" | sha256sum | cut -c1-16)…," \
       "cornell-box.png $(sha256sum <"$1/cornell-box.png" | cut -c1-16)…"
}

# 3. The Cornell box through the compose farm against the embedded farm render.
small=$(scene small 128 1)
job=$("$bin/farm" submit "$small")
"$bin/farm" watch "$job" >"$work/watch1.log" 2>&1 || { cat "$work/watch1.log" >&2; fail "job $job did not succeed"; }
"$bin/farm" fetch "$job" -o "$work/farm-small" --name cornell-box >/dev/null
step "compose farm rendered $small as $job: $(grep -o 'took .*' "$work/watch1.log" | tail -1)"
leases_a=$(leases_granted "$FARM_METRICS_PORT")
leases_b=$(leases_granted "$FARM_METRICS_B_PORT")
[ "$leases_a" -gt 0 ] && [ "$leases_b" -gt 0 ] ||
  fail "the workers did not talk to both replicas: leases granted by coordinator-a $leases_a, coordinator-b $leases_b"
echo "compose-test:   leases granted by coordinator-a $leases_a, by coordinator-b $leases_b"
"$bin/farm" render "$small" -o "$work/host-small" --workers 2 >/dev/null 2>&1 || fail "farm render"
step "host farm render of the same scene"
same "$work/farm-small" "$work/host-small"

# 3b. A coordinator keeps nothing of its own: its blobs are in the object store, its state
# in Redis, so a new coordinator container (its anonymous volume removed too) serves the job.
# Folders do not count: the builder's scratch folder stays, empty, between builds (a
# snapshot file lives there only while it is built and streamed into the object store).
for c in coordinator-a coordinator-b; do
  kept=$(dc exec -T "$c" find /var/lib/farm ! -type d) || fail "find in $c"
  [ -z "$kept" ] || fail "$c keeps files on its own disk: $kept"
done
stored_kb=$(dc exec -T objectstore du -sk /data | cut -f1)
dc rm -fsv coordinator-a >"$work/rm.log" 2>&1 || { cat "$work/rm.log" >&2; fail "docker-compose rm coordinator-a"; }
dc up -d coordinator-a >"$work/up2.log" 2>&1 || { cat "$work/up2.log" >&2; fail "docker-compose up coordinator-a"; }
wait_healthy
"$bin/farm" fetch "$job" -o "$work/farm-small-again" --name cornell-box >/dev/null
same "$work/farm-small" "$work/farm-small-again"
step "a new coordinator-a container served $job from Redis and the object store (${stored_kb} KB in its bucket's volume)"

# kill_mid_render SCENE SERVICE OUT: submits SCENE, SIGKILLs the first container of
# SERVICE while one of its render tiles is leased, and fetches the job once it succeeds
# into OUT.
kill_mid_render() {
  local job killed="" leased state left retried
  job=$("$bin/farm" submit "$1")
  for _ in $(seq 600); do
    leased=$("$bin/farm" tasks "$job" 2>/dev/null | awk '$2 == "render" && $3 == "leased"' || true)
    if [ -n "$leased" ]; then
      killed=$(dc ps -q "$2" | awk 'NR == 1')  # awk reads it all: head could SIGPIPE docker-compose under pipefail
      docker kill "$killed" >/dev/null
      break
    fi
    state=$("$bin/farm" status "$job" | awk '$1 == "state" {print $2}')
    [ "$state" = succeeded ] || [ "$state" = failed ] || [ "$state" = cancelled ] && break
    sleep 0.2
  done
  [ -n "$killed" ] || fail "job $job left the render phase before a $2 container could be killed"
  left=$("$bin/farm" tasks "$job" | awk '$2 == "render" && $3 != "succeeded"' | wc -l)
  step "killed $2 container ${killed:0:12} mid-render ($left render tasks unfinished)"
  "$bin/farm" watch "$job" >"$work/watch-$2.log" 2>&1 || { cat "$work/watch-$2.log" >&2; fail "job $job did not survive the kill"; }
  "$bin/farm" fetch "$job" -o "$3" --name cornell-box >/dev/null
  retried=$("$bin/farm" tasks "$job" | awk 'NR > 1 && $4 > 1' | wc -l)
  step "job $job succeeded after the kill ($retried tasks took more than one attempt): $(grep -o 'took .*' "$work/watch-$2.log" | tail -1)"
}

# 4. Kill a worker container while tiles render.
big=$(scene big 256 4)
kill_mid_render "$big" worker "$work/farm-big"
"$bin/farm" render "$big" -o "$work/host-big" --workers 2 >/dev/null 2>&1 || fail "farm render"
step "host farm render of the same scene"
same "$work/farm-big" "$work/host-big"

# 5. Kill a coordinator container while tiles render: the other replica carries on, for the
# workers (the alias `coordinator` now resolves to it alone) and for the host CLI.
kill_mid_render "$big" coordinator-a "$work/farm-big-again"
same "$work/farm-big-again" "$work/host-big"
