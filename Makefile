# The two commands users and CI type: `make demo` and `make test`. Each installs what is
# missing (scripts/install-deps.sh), builds, and runs.
BUILD_DIR ?= build
BIN := $(BUILD_DIR)/bin
JOBS ?= $(shell nproc)
SCENE ?= scenes/cornell-box.json
# Go's usual install folder, for shells whose PATH lacks it.
export PATH := $(PATH):/usr/local/go/bin

.PHONY: demo test build deps cpp go check-proto test-cpp check-dashboard test-go test-python fuzz fault-full limits bench compose-test test-blender blender-addon clean

demo: build
	$(BIN)/farm render $(SCENE) -o out/ --workers 2

test: build check-proto check-dashboard test-cpp test-go test-python test-blender fuzz compose-test

deps:
	@scripts/install-deps.sh

build: deps cpp go

cpp:
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build $(BUILD_DIR) -j $(JOBS)

go:
	go build -o $(BIN)/farm ./cmd/farm

check-proto:
	@scripts/gen-proto.sh --check

# The dashboard's built front end (services/dashboard/web/dist) is committed so that
# go build embeds it without npm; this rebuilds it and fails if the commit is stale.
check-dashboard:
	@services/dashboard/web/build.sh --check

test-cpp: cpp
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

# Integration and stiff tests under tests/ find the binaries through FARM_BIN_DIR; packages
# run one at a time (-p 1) because those suites start real farms and time their kills.
test-go: go
	@unformatted=$$(gofmt -l $$(git ls-files '*.go')); \
	  if [ -n "$$unformatted" ]; then echo "gofmt needed: $$unformatted"; exit 1; fi
	go vet ./...
	FARM_BIN_DIR=$(abspath $(BIN)) go test -p 1 -count=1 -timeout 30m ./...

# The Python SDK (client/python), pip-installed into $(BUILD_DIR)/py-venv as a user would
# install it, tested with pytest against a real coordinator and worker (about 10 s).
test-python: cpp go
	@scripts/install-deps.sh --python $(BUILD_DIR)/py-venv
	cd client/python && FARM_BIN_DIR=$(abspath $(BIN)) $(abspath $(BUILD_DIR))/py-venv/bin/python -m pytest -q

# Runs every fuzz target (scene parsing, validation and planning; request payloads) for a
# bounded time (FUZZTIME each, or 20 s split between them), prints each one's executions
# and rate, and fails below 1000 executions a second; failing inputs are kept under each
# package's testdata/fuzz. The list of targets is in scripts/fuzz.sh.
fuzz:
	scripts/fuzz.sh

# Issue 5's full fault-and-load numbers (20 worker kills, 10 coordinator kills, 100 jobs
# from 10 clients, lease throughput against Redis) and issue 12's job at the limit (95,539
# tasks on Redis); make test runs the same tests with fewer trials and a smaller job.
fault-full: build
	FARM_BIN_DIR=$(abspath $(BIN)) go test -count=1 -v -timeout 30m ./tests/fault/ \
	  -worker-kill-trials 20 -coordinator-kill-trials 10 -load-jobs 100 -load-clients 10 \
	  -limit-tiles 65536 -limit-shards 10000

# Issue 12's jobs at the size limits (the largest snapshot, composite, film and mesh), each
# on a farm of its own, printing time and peak memory; make test runs them reduced. About
# 25 minutes and 3 GB of memory on 2 cores (tests/README.md, "Limits").
limits: build
	FARM_BIN_DIR=$(abspath $(BIN)) go test -count=1 -v -timeout 3h ./tests/limits/ -limits.full

# Issue 7's docker-compose farm, for real: starts a Docker engine if none runs, builds the
# images, renders the Cornell box on Redis + object store + coordinator + dashboard + 2
# worker containers, checks it byte-identical to farm render, replaces the coordinator's
# container (it keeps nothing of its own), kills a worker mid-job, tears down. The last
# step of make test (about a minute and a half with the images cached, three cold; needs
# root for dockerd).
compose-test: build
	deploy/test-compose.sh

# Prints figures (photons traced per second, kd-tree build time, nearest-k queries per
# second against nanoflann in the same run, the atrium's time and memory, the relative MSE
# against Mitsuba 3, which only this target installs, in $(BUILD_DIR)/bench-venv); never
# part of make test.
bench: build
	@scripts/install-deps.sh --bench $(BUILD_DIR)/bench-venv
	BENCH_PYTHON=$(abspath $(BUILD_DIR))/bench-venv/bin/python bench/run.sh $(BUILD_DIR)

# Issue 16's Blender add-on (client/blender): its conversions' unit tests and a scene built
# with bpy, exported by the add-on installed through Blender's installer, rendered on a
# real coordinator with two workers and checked. bpy (Blender as a Python module) lives in
# its own virtual environment, $(BUILD_DIR)/blender-venv: a 374 MB download, about 1 GB
# installed, from 35 s to nearly 3 minutes to fetch and install here (the network decides;
# the tests themselves take some 20 s). make test runs it: it is all of the tests.
# pytest runs as the venv's script, not `python -m pytest`, which would put client/blender
# on sys.path and import the add-on from the source tree instead of where Blender's
# installer put it.
test-blender: cpp go
	@scripts/install-deps.sh --blender $(BUILD_DIR)/blender-venv
	cd client/blender && FARM_BIN_DIR=$(abspath $(BIN)) $(abspath $(BUILD_DIR))/blender-venv/bin/pytest -q tests

# The add-on as a zip for Blender's installer (client/blender/README.md).
blender-addon:
	@mkdir -p $(BUILD_DIR)
	python3 client/blender/package.py $(BUILD_DIR)/photonfarm-blender.zip

clean:
	rm -rf $(BUILD_DIR) out
