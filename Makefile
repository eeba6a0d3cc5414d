# wiresketch build. `make` builds build/wiresketch and build/libwiresketch.a;
# `make test` builds and runs every test; `make clean` removes build/.
# Options: NATIVE=1 adds -march=native (not portable to older CPUs);
#          SANITIZE=1 builds with ASan+UBSan into build/san.

CC       ?= cc
OPT      ?= -O2
CFLAGS   += -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(OPT) -g -Wall -Wextra \
            -Wno-unused-parameter -fopenmp -Isrc -Inn \
            $(shell pkg-config --cflags openblas libpng zlib libcjson)
LDLIBS   += $(shell pkg-config --libs openblas libpng zlib libcjson) -lgif -lm -fopenmp
BUILD    ?= build

ifeq ($(NATIVE),1)
CFLAGS   += -march=native
endif
ifeq ($(SANITIZE),1)
BUILD    := build/san
CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDLIBS   += -fsanitize=address,undefined
endif

LIB_SRC   := $(wildcard src/*.c) $(wildcard nn/*.c)
CLI_SRC   := $(wildcard src/cli/*.c)
TEST_SRC  := $(wildcard tests/test_*.c)
LIB_OBJ   := $(LIB_SRC:%.c=$(BUILD)/obj/%.o)
CLI_OBJ   := $(CLI_SRC:%.c=$(BUILD)/obj/%.o)
TEST_BIN  := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
HEADERS   := $(wildcard src/*.h) $(wildcard nn/*.h) $(wildcard src/cli/*.h) tests/check.h

.PHONY: all test clean bench demo
all: $(BUILD)/wiresketch $(BUILD)/libwiresketch.a $(BUILD)/embed_example

$(BUILD)/obj/%.o: %.c $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/libwiresketch.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/wiresketch: $(CLI_OBJ) $(BUILD)/libwiresketch.a
	$(CC) $(CFLAGS) $^ -o $@ $(LDLIBS)

$(BUILD)/embed_example: tools/embed_example.c $(BUILD)/libwiresketch.a $(HEADERS)
	$(CC) $(CFLAGS) $< $(BUILD)/libwiresketch.a -o $@ $(LDLIBS)

$(BUILD)/tests/%: tests/%.c $(BUILD)/libwiresketch.a $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests $< $(BUILD)/libwiresketch.a -o $@ $(LDLIBS)

test: all $(TEST_BIN)
	@BUILD=$(BUILD) bash tests/run.sh $(TEST_BIN)

demo: all
	@BUILD=$(BUILD) bash tools/demo.sh

clean:
	rm -rf build
