# Chn unit library - build, test, install, demo.
#   make              the library units, examples and tools into $(BUILD)
#                     (incremental: only what changed is rebuilt)
#   make test         the regression suite (FPCUnit + heap check + legacy modes)
#   make test T=DF1   only tests whose name contains DF1
#   make install      units (and sources) where Debian's fpc finds them;
#                     PREFIX=/usr (default), DESTDIR=, or PREFIX=$HOME/.fppkg
#   make uninstall    removes what install put there
#   make demo         a DF1 exchange on this machine, no hardware needed
#   make bench        codec and channel benchmarks
#   make fuzz         random-mutation fuzzing of the codecs, ChnPccc, the IEC 101 ASDUs and every
#                     layer's numeric parameters (SECONDS=10)
#   make soak         every protocol over a noisy pty line between two
#                     processes (SECONDS=10 per scenario, or COUNT=messages;
#                     SEED=, ONLY=name); docs/reliability.md
#   make wintest      the suite as win64 programs under Wine (docs/Windows.md)
#   make mutate       mutation testing: each mutant of tests/mutants/mutants.txt
#                     must fail its tests (slow; ONLY=id); make mutate-check
#                     only checks that every listed line is still there
#   make clean
# Optional: SYNAPSE_DIR=/path/to/synapse builds the Synapse serial backend.
#
# Layout: src/ is the library and nothing else; tools/lib/ holds units that
# only tools use (the simulator's table, the frame decoder); tests/support/
# only tests. Release units never see tests/.

FPC      ?= fpc
BUILD    ?= build
UNITDIR  := $(BUILD)/units
TOOLUNITDIR := $(BUILD)/tool-units
BINDIR   := $(BUILD)/bin
TUNITDIR := $(BUILD)/test-units
TBINDIR  := $(BUILD)/test-bin
DEB_PACKAGES := fp-compiler fp-units-rtl fp-units-base fp-units-fcl

SYNAPSE_FLAGS := $(if $(SYNAPSE_DIR),-Fu$(SYNAPSE_DIR) -Fi$(SYNAPSE_DIR) -dCHN_SYNAPSE)
COMMON   := -Fisrc -v0ew -l-
# library units: warnings are errors; release code is optimised
UNITFLAGS := $(COMMON) $(SYNAPSE_FLAGS) -Fusrc -O2 -Sew -FU$(UNITDIR) -FE$(BINDIR)
# examples, tools, benchmarks: the compiled library (as an installed one
# would be used; Synapse's units too, so they are not rebuilt with -Sew),
# plus tools/lib
PROGFLAGS := $(COMMON) $(if $(SYNAPSE_DIR),-dCHN_SYNAPSE) -Fu$(UNITDIR) -Futools/lib -O2 -Sew \
             -FU$(TOOLUNITDIR) -FE$(BINDIR)
# tests: range, overflow and stack checks, heaptrc, line info (and -Xs-:
# Debian's fpc.cfg strips it otherwise, and failures could not say where);
# -B rebuilds everything, as FPC's one-second timestamps can miss a quick edit
TESTFLAGS := $(COMMON) $(SYNAPSE_FLAGS) -Fusrc -Futools/lib -Futests/support -B -Cr -Co -Ct -gh -gl -Xs- \
             -Fu$(BUILD)/fpcunit -FU$(TUNITDIR) -FE$(TBINDIR) -Fi$(BUILD)
# FPCUnit rebuilt from Debian's fpc-source without optimisation, so that a
# failing assert's location names the test's own line (the prebuilt one
# loses the caller's frame); without fpc-source the prebuilt one is used.
FPCUNIT_SRC = /usr/share/fpcsrc/$(shell $(FPC) -iV)/packages/fcl-fpcunit/src

# Units that only build on another OS or with an optional library.
ifeq ($(OS),Windows_NT)
OS_UNITS := src/ChnPortUnix.pas src/ChnPty.pas
else
OS_UNITS := src/ChnPortWin.pas
endif
OPTIONAL_UNITS := $(if $(SYNAPSE_DIR),,src/ChnPortSynapse.pas) $(OS_UNITS)
LIBSRC   := $(wildcard src/*.pas) src/chn.inc
UNITS    := $(filter-out $(OPTIONAL_UNITS),$(wildcard src/*.pas))
TOOLLIB  := $(wildcard tools/lib/*.pas)
EXAMPLES := $(wildcard examples/*.pas)
TOOLS    := $(wildcard tools/*.pas)
BENCHES  := $(wildcard bench/*.pas)
TESTUNITS := $(wildcard tests/Test*.pas)
PROGRAMS := $(EXAMPLES) $(TOOLS)
PROGBINS := $(addprefix $(BINDIR)/,$(basename $(notdir $(PROGRAMS))))
BENCHBINS := $(addprefix $(BINDIR)/,$(basename $(notdir $(BENCHES))))

.PHONY: all units examples tools test demo bench fuzz soak wintest clean check-fpc \
        install uninstall mutate mutate-check

all: units $(PROGBINS) chn.lpk
examples: $(addprefix $(BINDIR)/,$(basename $(notdir $(EXAMPLES))))
tools: $(addprefix $(BINDIR)/,$(basename $(notdir $(TOOLS))))

check-fpc:
	@command -v $(FPC) >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "fpc not found: installing $(DEB_PACKAGES)"; \
	    apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $(DEB_PACKAGES); \
	  else \
	    echo "fpc not found. Install it with:"; \
	    echo "  sudo apt-get install -y $(DEB_PACKAGES)"; exit 1; \
	  fi; }

# Every library unit, compiled once by one fpc call on a generated unit
# that uses them all; fpc itself recompiles only what changed.
units: $(BUILD)/units.stamp
$(BUILD)/units.stamp: $(LIBSRC) | check-fpc
	@mkdir -p $(UNITDIR) $(BINDIR)
	@# compiled units that "fpc -Fusrc prog.pas" left beside the sources
	@# would be taken as current and never reach $(UNITDIR)
	@if [ -n "$$(ls src/*.ppu tools/lib/*.ppu 2>/dev/null)" ]; then \
	  echo "note: removing compiler output left in src/ or tools/lib/"; \
	  rm -f src/*.ppu src/*.o src/*.rsj tools/lib/*.ppu tools/lib/*.o tools/lib/*.rsj; fi
	@$(if $(SYNAPSE_DIR),$(FPC) $(COMMON) $(SYNAPSE_FLAGS) -O2 -FU$(UNITDIR) -FE$(BINDIR) $(SYNAPSE_DIR)/synaser.pas >/dev/null;) true
	@{ echo 'unit chnall; interface uses'; \
	   echo '$(basename $(notdir $(UNITS)))' | sed 's/ /, /g'; \
	   echo '; implementation end.'; } > $(BUILD)/chnall.pas
	@echo "fpc src/*.pas"
	@$(FPC) $(UNITFLAGS) $(BUILD)/chnall.pas
	@touch $@

# The Lazarus package lists every unit of src/.
chn.lpk: $(wildcard src/*.pas) tools/mklpk.sh
	@bash tools/mklpk.sh

# Which sources each program depends on (from the uses clauses).
$(BUILD)/deps.mk: $(LIBSRC) $(TOOLLIB) $(PROGRAMS) $(BENCHES) tools/mkdeps.sh
	@mkdir -p $(BUILD)
	@bash tools/mkdeps.sh $(BINDIR) src tools/lib -- $(PROGRAMS) $(BENCHES) > $@.tmp && mv $@.tmp $@
-include $(BUILD)/deps.mk

# One program: its units are current (units.stamp, order only: a program
# is rebuilt when a source it uses changed, see deps.mk), so fpc compiles
# the program (and any tools/lib unit it uses) and links.
$(PROGBINS) $(BENCHBINS): src/chn.inc | $(BUILD)/units.stamp
	@mkdir -p $(TOOLUNITDIR)
	@echo "fpc $(filter %/$(notdir $@).pas,$(PROGRAMS) $(BENCHES))"
	@$(FPC) $(PROGFLAGS) $(filter %/$(notdir $@).pas,$(PROGRAMS) $(BENCHES))

# The runner's uses clause is generated from tests/Test*.pas, so adding a
# test unit needs no edit anywhere else. Units that need Unix as a whole
# (ptys) are listed here and built only there; single Unix-only tests are
# {$IFDEF UNIX} in their unit.
UNIX_TESTS := TestChnPty TestChnTcpSer2net TestFT12Examples TestFaultCycling TestIec101Examples \
              TestIec101SlaveTool TestIec101Docs
comma := ,
uses_entry = $(if $(filter $(1),$(UNIX_TESTS)),'{$$IFDEF UNIX}$(1)$(comma){$$ENDIF}','$(1)$(comma)')
$(BUILD)/testunits.inc: $(TESTUNITS)
	@mkdir -p $(BUILD)
	@printf '%s\n' $(foreach t,$(basename $(notdir $(TESTUNITS))),$(call uses_entry,$(t))) > $@.tmp
	@cmp -s $@.tmp $@ 2>/dev/null && rm -f $@.tmp || mv $@.tmp $@

$(BUILD)/fpcunit/stamp:
	@mkdir -p $(BUILD)/fpcunit
	@if [ -d $(FPCUNIT_SRC) ]; then for u in fpcunit testregistry; do \
	  $(FPC) -v0 -O- -gl -Xs- -FU$(BUILD)/fpcunit -Fu$(FPCUNIT_SRC) $(FPCUNIT_SRC)/$$u.pp >/dev/null || exit 1; done; \
	else echo "note: no fpc-source: failing asserts are located by address only"; fi; touch $@

test: all $(BUILD)/testunits.inc $(BUILD)/fpcunit/stamp
	@mkdir -p $(TUNITDIR) $(TBINDIR)
	@$(FPC) $(TESTFLAGS) tests/runtests.pas >$(BUILD)/test-build.log 2>&1 || { cat $(BUILD)/test-build.log; echo "0 passed, 1 failed"; exit 1; }
	@$(FPC) $(SOAKFLAGS) tests/soak/soak.pas >>$(BUILD)/test-build.log 2>&1 || { cat $(BUILD)/test-build.log; echo "0 passed, 1 failed"; exit 1; }
	@BUILD=$(BUILD) FPC=$(FPC) T="$(T)" bash tests/run.sh

demo: all
	@bash tools/demo.sh $(BUILD)

bench: $(BENCHBINS) $(BINDIR)/chntap $(BINDIR)/plcconc $(BINDIR)/df1sim
	@set -e; for b in $(BENCHBINS); do $$b; done

# Random-mutation fuzzing of the three codecs, of ChnPccc (addresses,
# plans, requests, reply decoding), of ChnIec101Asdu, and every key of
# every layer with numbers built to break a parser (fuzzparams), with
# run-time checks on;
# SECONDS=n for longer runs, SEED=n to repeat one.
SECONDS ?= 10
FUZZERS := fuzzcodecs fuzzpccc fuzzasdu fuzzparams
# the soak program: test flags, on the units the test build just made
SOAKFLAGS = $(filter-out -B,$(TESTFLAGS))
fuzz: units
	@mkdir -p $(TUNITDIR) $(TBINDIR)
	@rm -f $(BUILD)/fuzz-build.log
	@set -e; for f in $(FUZZERS); do \
	  $(FPC) $(TESTFLAGS) tests/fuzz/$$f.pas >>$(BUILD)/fuzz-build.log 2>&1 || { cat $(BUILD)/fuzz-build.log; exit 1; }; done
	@set -e; for f in $(FUZZERS); do rm -f $(BUILD)/fuzz-heap.log; \
	  HEAPTRC="log=$(BUILD)/fuzz-heap.log" $(TBINDIR)/$$f $(SECONDS) $(SEED); done

# The soak (docs/reliability.md): SECONDS per scenario or COUNT messages
# per scenario; SEED= the first NOISE seed; ONLY= scenarios whose name
# contains it. make test runs every scenario for 2 s.
soak: all
	@mkdir -p $(TUNITDIR) $(TBINDIR)
	@$(FPC) $(TESTFLAGS) tests/soak/soak.pas >$(BUILD)/soak-build.log 2>&1 || { cat $(BUILD)/soak-build.log; exit 1; }
	@rm -f $(BUILD)/soak-heap.log; HEAPTRC="log=$(BUILD)/soak-heap.log" $(TBINDIR)/soak \
	  $(if $(COUNT),--count=$(COUNT),--seconds=$(SECONDS)) $(if $(SEED),--seed=$(SEED)) \
	  $(if $(ONLY),--only=$(ONLY)) --df1sim=$(BINDIR)/df1sim

# Mutation testing (docs/reliability.md): the tree is copied to a scratch
# folder and built there (with BUILD=build), so the flags are the test
# build's for that folder; not part of test.
mutate:
	@FPC=$(FPC) BUILD=build TESTFLAGS="$(filter-out -B,$(subst $(BUILD)/,build/,$(TESTFLAGS)))" \
	  ONLY="$(ONLY)" bash tests/mutants/mutate.sh run $(MUTANTS)
mutate-check:
	@bash tests/mutants/mutate.sh check $(MUTANTS)

# Cross-built for win64 and run under Wine; not part of test (CI has no Wine).
wintest: all $(BUILD)/testunits.inc
	@BUILD=$(BUILD) FPC=$(FPC) T="$(T)" SYNAPSE_DIR="$(SYNAPSE_DIR)" bash tools/wintest.sh

# ---------------------------------------------------------------- install
# Debian's /etc/fpc.cfg searches /usr/lib/<multiarch>/fpc/<version>/units/
# <target>/* and, per user, ~/.fppkg/lib/fpc/<version>/units/<target>/*:
# the units go into a folder "chn" there, in lower case as fpc looks for
# them whatever case a program's uses clause has; the sources (for
# debugging and the Lazarus package) into $(PREFIX)/share/chn.
PREFIX   ?= /usr
FPCVER    = $(shell $(FPC) -iV)
FPCTARGET = $(shell $(FPC) -iTP)-$(shell $(FPC) -iTO)
MULTIARCH = $(shell gcc -print-multiarch 2>/dev/null || dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null)
FPCLIBDIR = $(if $(filter /usr,$(PREFIX)),$(PREFIX)/lib/$(MULTIARCH)/fpc,$(PREFIX)/lib/fpc)
INSTALL_UNITDIR ?= $(FPCLIBDIR)/$(FPCVER)/units/$(FPCTARGET)/chn
INSTALL_SRCDIR  ?= $(PREFIX)/share/chn

install: units
	@set -e; d='$(DESTDIR)$(INSTALL_UNITDIR)'; s='$(DESTDIR)$(INSTALL_SRCDIR)'; \
	mkdir -p "$$d" "$$s/src"; \
	for u in $(basename $(notdir $(UNITS))); do l=$$(echo $$u | tr A-Z a-z); \
	  install -m 644 $(UNITDIR)/$$u.ppu "$$d/$$l.ppu"; \
	  install -m 644 $(UNITDIR)/$$u.o "$$d/$$l.o"; done; \
	install -m 644 $(LIBSRC) "$$s/src/"; install -m 644 chn.lpk "$$s/"; \
	echo "installed units in $$d, sources in $$s"

uninstall:
	rm -rf '$(DESTDIR)$(INSTALL_UNITDIR)' '$(DESTDIR)$(INSTALL_SRCDIR)'

clean:
	rm -rf $(BUILD)
