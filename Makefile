# wiresketch build. `make` builds build/wiresketch and build/libwiresketch.a;
# `make test` builds and runs every test (the repository alone: scenes
# come from tests/fixtures); `make test-scenes SCENES=DIR` runs the scene,
# metrics and render checks on DIR/rose and DIR/duck (../shared/scenes by
# default); `make check-layers` checks the layering (nn/ stands alone, no
# include cycle) and prints the folders' order; `make clean` removes build/.
# Options: NATIVE=1 adds -march=native (not portable to older CPUs);
#          SANITIZE=1 builds with ASan+UBSan into build/san (or BUILD=...).
#          MPI=1 builds with Open MPI into build/mpi, for `mpirun -np N
#          build/mpi/wiresketch fit ...` (`bash tools/setup.sh mpi` installs it).
# `make test-mpi` builds that and checks that fits on 1, 2 and 3 ranks agree.
# `make fuzz` builds tests/fuzz/fuzz_*.c with clang's libFuzzer into
# build/fuzz and runs each target FUZZ_SECONDS (60) on its seed corpus.
# Build lines are short ("CC file"); V=1 prints the whole commands.

CC       ?= cc
OPT      ?= -O2
CFLAGS   += -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(OPT) -g -Wall -Wextra \
            -Wno-unused-parameter -fopenmp -fPIC -Isrc -I. \
            $(shell pkg-config --cflags openblas libpng zlib libcjson libjpeg)
LDLIBS   += $(shell pkg-config --libs openblas libpng zlib libcjson libjpeg) -lgif -lm -fopenmp

ifeq ($(NATIVE),1)
CFLAGS   += -march=native
endif
ifeq ($(MPI),1)
BUILD    ?= build/mpi
CFLAGS   += -DWS_MPI $(shell pkg-config --cflags ompi-c)
LDLIBS   += $(shell pkg-config --libs ompi-c)
endif
ifeq ($(SANITIZE),1)
BUILD    ?= build/san
CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDLIBS   += -fsanitize=address,undefined
endif
ifeq ($(FUZZ),1)
CFLAGS   += -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -Wno-pass-failed \
            -fno-sanitize-recover=undefined
endif
BUILD    ?= build

# The compiler writes each object's header dependencies beside it (-MMD),
# with a phony target per header (-MP) so that a removed header does not
# stop the build: touching a header rebuilds only the files that include it.
CFLAGS   += -MMD -MP
ifeq ($(V),1)
Q        :=
quiet     = @:
else
Q        := @
quiet     = @printf '  %-6s %s\n'
endif

LIB_SRC   := $(filter-out src/cli/%,$(wildcard src/*/*.c)) $(wildcard nn/*.c nn/*/*.c)
CLI_SRC   := $(wildcard src/cli/*.c)
TEST_SRC  := $(wildcard tests/test_*.c)
LIB_OBJ   := $(LIB_SRC:%.c=$(BUILD)/obj/%.o)
CLI_OBJ   := $(CLI_SRC:%.c=$(BUILD)/obj/%.o)
TEST_BIN  := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
HEADERS   := $(wildcard src/*.h src/*/*.h nn/*.h nn/*/*.h) tests/check.h tests/test_util.h

.PHONY: all test test-scenes check-layers clean install uninstall bench demo fuzz fuzz-build test-mpi bench-mpi
all: $(BUILD)/wiresketch $(BUILD)/libwiresketch.a $(BUILD)/embed_example

# nn/'s vector kernels (fastmath.h) fuse multiply-adds where the CPU has
# them; plain x86-64 code has no FMA, so elsewhere this changes nothing.
$(BUILD)/obj/nn/%.o: CFLAGS += -ffp-contract=fast

$(BUILD)/obj/%.o: %.c Makefile
	@mkdir -p $(dir $@)
	$(quiet) CC $<
	$(Q)$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/libwiresketch.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	$(quiet) AR $@
	$(Q)rm -f $@ && ar rcs $@ $^

$(BUILD)/wiresketch: $(CLI_OBJ) $(BUILD)/libwiresketch.a
	$(quiet) LINK $@
	$(Q)$(CC) $(CFLAGS) $^ -o $@ $(LDLIBS)

$(BUILD)/embed_example: tools/embed_example.c $(BUILD)/libwiresketch.a Makefile
	$(quiet) LINK $@
	$(Q)$(CC) $(CFLAGS) -MF $@.d -MT $@ $< $(BUILD)/libwiresketch.a -o $@ $(LDLIBS)

$(BUILD)/tests/%: tests/%.c $(BUILD)/libwiresketch.a Makefile
	@mkdir -p $(dir $@)
	$(quiet) TEST $@
	$(Q)$(CC) $(CFLAGS) -MF $@.d -MT $@ -Itests $< $(BUILD)/libwiresketch.a -o $@ $(LDLIBS)

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_BIN:=.d) $(BUILD)/embed_example.d

# `make install PREFIX=/usr/local DESTDIR=` installs the program, the static
# and the shared library (soname libwiresketch.so.SOVERSION), the public
# headers under include/wiresketch/ (src/wiresketch.h and the headers it
# includes, as the compiler finds them, their folders kept: #include
# "wiresketch.h" with -I PREFIX/include/wiresketch), wiresketch.pc and the man page
# (made from the program's --help by tools/make_man.sh); `make uninstall`
# with the same PREFIX and DESTDIR removes them.
VERSION   := 0.1.0
SOVERSION := 0
PREFIX    ?= /usr/local
DESTDIR   ?=
SHLIB     := libwiresketch.so.$(VERSION)
ROOT      := $(DESTDIR)$(PREFIX)

# The version and the commit the program is built from (base/version.c):
# BUILD/build_id.txt holds them and is rewritten only when they change, so
# that version.o alone rebuilds then ("unknown" outside a git checkout).
BUILD_ID  := $(VERSION) $(shell [ -e .git ] && git describe --always --dirty 2>/dev/null || echo unknown)
.PHONY: build-id
$(BUILD)/build_id.txt: build-id
	@mkdir -p $(dir $@)
	@echo '$(BUILD_ID)' | cmp -s - $@ || echo '$(BUILD_ID)' > $@
$(BUILD)/obj/src/base/version.o: $(BUILD)/build_id.txt
$(BUILD)/obj/src/base/version.o: CFLAGS += -DWS_VERSION='"$(word 1,$(BUILD_ID))"' -DWS_COMMIT='"$(word 2,$(BUILD_ID))"'

$(BUILD)/$(SHLIB): $(LIB_OBJ)
	$(CC) -shared -Wl,-soname,libwiresketch.so.$(SOVERSION) $^ -o $@ $(LDLIBS)

$(BUILD)/wiresketch.1: $(BUILD)/wiresketch tools/make_man.sh
	bash tools/make_man.sh $(BUILD)/wiresketch $(VERSION) > $@.tmp && mv $@.tmp $@

# The public headers, one a line: wiresketch.h's closure under #include.
$(BUILD)/public_headers: $(HEADERS) Makefile
	@mkdir -p $(dir $@)
	$(CC) $(filter-out -MMD -MP,$(CFLAGS)) -MM -MT public src/wiresketch.h | tr -s ' \\' '\n\n' | \
	    grep '\.h$$' | sort -u > $@.tmp && mv $@.tmp $@

$(BUILD)/wiresketch.pc: Makefile
	@mkdir -p $(dir $@)
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}/lib' 'includedir=$${prefix}/include' '' \
	    'Name: wiresketch' 'Description: 3D wireframe sketches of an object from multi-view photos' \
	    'Version: $(VERSION)' 'Requires.private: openblas libpng zlib libcjson libjpeg' \
	    'Libs: -L$${libdir} -lwiresketch' 'Libs.private: -lgif -lm -fopenmp' \
	    'Cflags: -I$${includedir}/wiresketch -D_POSIX_C_SOURCE=200809L' > $@

install: all $(BUILD)/$(SHLIB) $(BUILD)/wiresketch.1 $(BUILD)/wiresketch.pc $(BUILD)/public_headers
	install -d $(ROOT)/bin $(ROOT)/lib/pkgconfig $(ROOT)/include/wiresketch $(ROOT)/share/man/man1
	install -m 755 $(BUILD)/wiresketch $(ROOT)/bin/wiresketch
	install -m 644 $(BUILD)/libwiresketch.a $(ROOT)/lib/libwiresketch.a
	install -m 755 $(BUILD)/$(SHLIB) $(ROOT)/lib/$(SHLIB)
	ln -sf $(SHLIB) $(ROOT)/lib/libwiresketch.so.$(SOVERSION)
	ln -sf libwiresketch.so.$(SOVERSION) $(ROOT)/lib/libwiresketch.so
	for h in $$(cat $(BUILD)/public_headers); do \
	    install -D -m 644 $$h $(ROOT)/include/wiresketch/$${h#src/} || exit 1; done
	sed 's|^prefix=.*|prefix=$(PREFIX)|' $(BUILD)/wiresketch.pc > $(ROOT)/lib/pkgconfig/wiresketch.pc
	install -m 644 $(BUILD)/wiresketch.1 $(ROOT)/share/man/man1/wiresketch.1

uninstall:
	rm -f $(ROOT)/bin/wiresketch $(ROOT)/lib/libwiresketch.a $(ROOT)/lib/$(SHLIB) \
	    $(ROOT)/lib/libwiresketch.so.$(SOVERSION) $(ROOT)/lib/libwiresketch.so \
	    $(ROOT)/lib/pkgconfig/wiresketch.pc $(ROOT)/share/man/man1/wiresketch.1
	rm -rf $(ROOT)/include/wiresketch

test: check-layers all $(TEST_BIN)
	@BUILD=$(BUILD) bash tests/run.sh $(TEST_BIN)

# nn/ stands alone: besides tools/check_layers.py (no include outside nn/,
# no cycle among modules or folders), every nn/ file compiles without
# -Isrc -I. (syntax only: a few seconds).
NN_CFLAGS := -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -fopenmp $(shell pkg-config --cflags openblas)
check-layers:
	@python3 tools/check_layers.py
	@for f in $(wildcard nn/*.c nn/*/*.c); do $(CC) $(NN_CFLAGS) -fsyntax-only $$f || exit 1; done

SCENES   ?= ../shared/scenes
SCENE_TESTS := $(BUILD)/tests/test_scene $(BUILD)/tests/test_metrics $(BUILD)/tests/test_render
test-scenes: all $(SCENE_TESTS)
	@BUILD=$(BUILD) bash tests/run.sh --args $(SCENES) $(SCENE_TESTS)

test-mpi: all
	$(MAKE) MPI=1 build/mpi/wiresketch
	@bash tests/mpi/run.sh build/mpi/wiresketch

# `make bench-mpi`: the MPI tables of docs/RESULTS.md (measured steps on 1 and 2
# ranks, per-image costs, the model for 1..64 ranks).
bench-mpi: all weights/random-f32.bin
	$(MAKE) MPI=1 build/mpi/wiresketch
	bash tools/bench_mpi.sh

# Fuzzing (clang + libFuzzer; `bash tools/setup.sh fuzz` installs them). The
# library is rebuilt with clang and coverage into build/fuzz; each target
# runs FUZZ_SECONDS on its seed corpus, with tests/fuzz/TARGET.dict (or
# json.dict) as dictionary (new inputs land in build/fuzz/corpus/TARGET,
# crashes in build/fuzz/findings/TARGET).
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := $(patsubst tests/fuzz/fuzz_%.c,%,$(wildcard tests/fuzz/fuzz_*.c))
FUZZ_BIN     := $(FUZZ_TARGETS:%=build/fuzz/fuzz_%)

fuzz-build:
	$(MAKE) CC=clang FUZZ=1 BUILD=build/fuzz $(FUZZ_BIN)

build/fuzz/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_input.h $(BUILD)/libwiresketch.a $(HEADERS)
	$(CC) $(CFLAGS) -fsanitize=fuzzer -Itests/fuzz $< $(BUILD)/libwiresketch.a -o $@ $(LDLIBS)

fuzz: fuzz-build
	@for t in $(FUZZ_TARGETS); do \
	    mkdir -p build/fuzz/corpus/$$t build/fuzz/findings/$$t && \
	    echo "fuzz_$$t: $(FUZZ_SECONDS) s" && \
	    dict=tests/fuzz/$$t.dict; case $$t in scene|curves) dict=tests/fuzz/json.dict;; esac; \
	    OMP_NUM_THREADS=1 build/fuzz/fuzz_$$t build/fuzz/corpus/$$t tests/fuzz/corpus/$$t \
	        $$([ -f $$dict ] && echo -dict=$$dict) -max_total_time=$(FUZZ_SECONDS) -timeout=10 \
	        -rss_limit_mb=4096 -max_len=65536 -artifact_prefix=build/fuzz/findings/$$t/ \
	        2>build/fuzz/fuzz_$$t.log; \
	    rc=$$?; grep -E '^#[0-9]+[[:space:]]+DONE' build/fuzz/fuzz_$$t.log; \
	    if [ $$rc -ne 0 ]; then tail -n 40 build/fuzz/fuzz_$$t.log; exit 1; fi; \
	done

demo: all
	@BUILD=$(BUILD) bash tools/demo.sh

# `make bench`: every benchmark table of docs/RESULTS.md, "Speed and accuracy"
# (wiresketch bench). The f16 row and the peak-memory part need a ViT-B/32
# with random weights as f32 and f16 files: made once (about a minute).
bench: all weights/random-f32.bin weights/random-f16.bin
	$(BUILD)/wiresketch bench

weights/random-%.bin:
	python3 tools/make_random_weights.py $@ --dtype $*

clean:
	rm -rf build
