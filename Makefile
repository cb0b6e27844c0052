# Chn unit library - build, test, demo.
#   make            all units, examples and tools into $(BUILD)
#   make test       the regression suite (FPCUnit + heap check + legacy modes)
#   make test T=DF1 only tests whose name contains DF1
#   make demo       a DF1 exchange on this machine, no hardware needed
#   make bench      codec and channel benchmarks
#   make fuzz       random-mutation fuzzing of the codecs (SECONDS=10)
#   make wintest    the suite as win64 programs under Wine (docs/Windows.md)
#   make clean
# Optional: SYNAPSE_DIR=/path/to/synapse builds the Synapse serial backend.

FPC      ?= fpc
BUILD    ?= build
UNITDIR  := $(BUILD)/units
BINDIR   := $(BUILD)/bin
TUNITDIR := $(BUILD)/test-units
TBINDIR  := $(BUILD)/test-bin
DEB_PACKAGES := fp-compiler fp-units-rtl fp-units-base fp-units-fcl

SYNAPSE_FLAGS := $(if $(SYNAPSE_DIR),-Fu$(SYNAPSE_DIR) -Fi$(SYNAPSE_DIR) -dCHN_SYNAPSE)
COMMON   := -Fusrc -Fisrc -Futests/support $(SYNAPSE_FLAGS) -v0ew -l-
# units: warnings are errors; release code is optimised
UNITFLAGS := $(COMMON) -O2 -Sew -FU$(UNITDIR) -FE$(BINDIR)
# tests: range, overflow and stack checks, heaptrc, line info; -B rebuilds
# everything, as FPC's one-second timestamps can miss a quick edit
TESTFLAGS := $(COMMON) -B -Cr -Co -Ct -gh -gl -FU$(TUNITDIR) -FE$(TBINDIR) -Fi$(BUILD)

# Units that only build on another OS or with an optional library.
ifeq ($(OS),Windows_NT)
OS_UNITS := src/ChnPortUnix.pas src/ChnPty.pas
else
OS_UNITS := src/ChnPortWin.pas
endif
OPTIONAL_UNITS := $(if $(SYNAPSE_DIR),,src/ChnPortSynapse.pas) $(OS_UNITS)
UNITS    := $(filter-out $(OPTIONAL_UNITS),$(wildcard src/*.pas))
EXAMPLES := $(wildcard examples/*.pas)
TOOLS    := $(wildcard tools/*.pas)
BENCHES  := $(wildcard bench/*.pas)
TESTUNITS := $(wildcard tests/Test*.pas)

.PHONY: all units examples tools test demo bench fuzz wintest clean check-fpc dirs

all: units examples tools

check-fpc:
	@command -v $(FPC) >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "fpc not found: installing $(DEB_PACKAGES)"; \
	    apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $(DEB_PACKAGES); \
	  else \
	    echo "fpc not found. Install it with:"; \
	    echo "  sudo apt-get install -y $(DEB_PACKAGES)"; exit 1; \
	  fi; }

dirs:
	@mkdir -p $(UNITDIR) $(BINDIR) $(TUNITDIR) $(TBINDIR)

# Synapse is third-party code with warnings of its own: build it first
# without -Sew, so our units (built with -Sew) find its compiled units.
units: check-fpc dirs
	@set -e; $(if $(SYNAPSE_DIR),$(FPC) $(COMMON) -O2 -FU$(UNITDIR) -FE$(BINDIR) $(SYNAPSE_DIR)/synaser.pas >/dev/null;) \
	for u in $(UNITS); do $(FPC) $(UNITFLAGS) $$u; done

examples: units
	@set -e; for p in $(EXAMPLES); do $(FPC) $(UNITFLAGS) $$p; done

tools: units
	@set -e; for p in $(TOOLS); do $(FPC) $(UNITFLAGS) $$p; done

# The runner's uses clause is generated from tests/Test*.pas, so adding a
# test unit needs no edit anywhere else. Units that need Unix as a whole
# (ptys) are listed here and built only there; single Unix-only tests are
# {$IFDEF UNIX} in their unit.
UNIX_TESTS := TestChnPty
comma := ,
uses_entry = $(if $(filter $(1),$(UNIX_TESTS)),'{$$IFDEF UNIX}$(1)$(comma){$$ENDIF}','$(1)$(comma)')
$(BUILD)/testunits.inc: $(TESTUNITS) | dirs
	@printf '%s\n' $(foreach t,$(basename $(notdir $(TESTUNITS))),$(call uses_entry,$(t))) > $@.tmp
	@cmp -s $@.tmp $@ 2>/dev/null && rm -f $@.tmp || mv $@.tmp $@

test: all $(BUILD)/testunits.inc
	@$(FPC) $(TESTFLAGS) tests/runtests.pas >$(BUILD)/test-build.log 2>&1 || { cat $(BUILD)/test-build.log; echo "0 passed, 1 failed"; exit 1; }
	@BUILD=$(BUILD) FPC=$(FPC) T="$(T)" bash tests/run.sh

demo: all
	@bash tools/demo.sh $(BUILD)

bench: units
	@set -e; for p in $(BENCHES); do $(FPC) $(UNITFLAGS) $$p; $(BINDIR)/$$(basename $$p .pas); done

# Random-mutation fuzzing of the three codecs with run-time checks on;
# SECONDS=n for longer runs, SEED=n to repeat one.
SECONDS ?= 10
fuzz: units
	@$(FPC) $(TESTFLAGS) tests/fuzz/fuzzcodecs.pas >$(BUILD)/fuzz-build.log 2>&1 || { cat $(BUILD)/fuzz-build.log; exit 1; }
	@rm -f $(BUILD)/fuzz-heap.log; HEAPTRC="log=$(BUILD)/fuzz-heap.log" $(TBINDIR)/fuzzcodecs $(SECONDS) $(SEED)

# Cross-built for win64 and run under Wine; not part of test (CI has no Wine).
wintest: all $(BUILD)/testunits.inc
	@BUILD=$(BUILD) FPC=$(FPC) T="$(T)" SYNAPSE_DIR="$(SYNAPSE_DIR)" bash tools/wintest.sh

clean:
	rm -rf $(BUILD)
