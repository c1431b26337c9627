# The two commands of the README. Both install what is missing (Debian packages, via apt-get),
# configure and build first.
#   make run   - build, start granulabd on var/granulab.db, run the two-cube demo through it, keep serving
#   make test  - build, then run every test (ctest)
#   make docker-check - build the image for real (buildah) and check it serves a job (outside make test)
BUILD ?= build
JOBS ?= $(shell nproc)
DEBIAN_PACKAGES := cmake make g++ pkg-config libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev \
                   libsqlite3-dev libspdlog-dev libgtest-dev libgmock-dev \
                   libarchive-dev libssl-dev chromium python3-jsonschema python3-vtk9 python3-ase \
                   python3-venv python3-pip python3-pandas python3-meshio python3-gsd \
                   python3-nbclient python3-ipykernel
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: deps configure build test run bench clean docker-check

deps:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing missing Debian packages:" $$missing; \
	  $(SUDO) apt-get -o DPkg::Lock::Timeout=600 update && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends $$missing; \
	fi

configure: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD) -j $(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Only the two binaries it runs, not the test suite.
run: configure
	cmake --build $(BUILD) -j $(JOBS) --target granulabd granulab
	BUILD=$(BUILD) clients/demo.sh

bench: build
	$(BUILD)/bench/bench_contacts

# Not part of `make test`: builds docker/Dockerfile with buildah (its build stage runs every test) and checks
# that the image serves a job (docker/check.sh; root; about half an hour on 2 cores).
docker-check:
	$(SUDO) docker/check.sh

clean:
	rm -rf $(BUILD)
