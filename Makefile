# Chn unit library - build, test, install, demo.
#   make              the library units, examples and tools into $(BUILD)
#                     (incremental: only what changed is rebuilt)
#   make test         the regression suite (FPCUnit + heap check + legacy modes)
#   make test T=DF1   only tests whose name contains DF1
#   make install      units (and sources) where Debian's fpc finds them, the
#                     tools into $(PREFIX)/bin with man pages (help2man);
#                     PREFIX=/usr (default), DESTDIR=, or PREFIX=$HOME/.fppkg
#   make man          the tools' man pages into build/man (help2man)
#   make doc          the API reference (pasdoc) into build/doc
#   make uninstall    removes what install put there
#   make demo         a DF1 exchange on this machine, no hardware needed
#   make bench        codec and channel benchmarks
#   make fuzz         random-mutation fuzzing of the codecs, ChnPccc, the IEC 101 ASDUs and every
#                     layer's numeric parameters (SECONDS=10)
#   make soak         every protocol over a noisy pty line between two
#                     processes (SECONDS=10 per scenario, or COUNT=messages;
#                     SEED=, ONLY=name); docs/reliability.md
#   make wintest      the suite as win64 programs under Wine (docs/Windows.md)
#   make cross ARCH=armhf|aarch64      everything for ARM Linux, built by a
#                     cross compiler made once from Debian's fpc source in
#                     CROSS_CACHE (docs/ARM.md)
#   make crosstest ARCH=armhf|aarch64  the suite and the legacy programs
#                     for ARM under qemu-user
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

# The library is a folder per part under src/ (src/README.md): core, phys,
# trace, df1, iec, ics...; every part folder is searched. Per-OS code lives
# in a part's unix/ and win/ folders (units and the include files of
# portable units), as in Free Pascal's own packages; this OS's folder of
# src/phys is searched too. The optional Synapse backend builds only with
# SYNAPSE_DIR.
ifeq ($(OS),Windows_NT)
OSDIR    := win
else
OSDIR    := unix
endif
SRCDIRS  := $(patsubst %/,%,$(wildcard src/*/))
SRCPATH  := $(addprefix -Fu,$(SRCDIRS)) -Fusrc/phys/$(OSDIR)

SYNAPSE_FLAGS := $(if $(SYNAPSE_DIR),-Fu$(SYNAPSE_DIR) -Fi$(SYNAPSE_DIR) -dCHN_SYNAPSE)
COMMON   := -Fisrc -v0ew -l-
# library units: warnings are errors; release code is optimised
UNITFLAGS := $(COMMON) $(SYNAPSE_FLAGS) $(SRCPATH) -O2 -Sew -FU$(UNITDIR) -FE$(BINDIR)
# examples, tools, benchmarks: the compiled library (as an installed one
# would be used; Synapse's units too, so they are not rebuilt with -Sew),
# plus tools/lib; smart linked (-XX): only the routines a program reaches
# are in it, so it is smaller on disk and in memory (chngate 1.3 MB ->
# 0.6 MB, its resident size 0.8 MB less)
PROGFLAGS := $(COMMON) $(if $(SYNAPSE_DIR),-dCHN_SYNAPSE) -Fu$(UNITDIR) -Futools/lib -O2 -XX -Sew \
             -FU$(TOOLUNITDIR) -FE$(BINDIR)
# tests: range, overflow and stack checks, heaptrc, line info (and -Xs-:
# Debian's fpc.cfg strips it otherwise, and failures could not say where);
# -B rebuilds everything, as FPC's one-second timestamps can miss a quick edit;
# CHN_HEAPTRC: a program that would use the C allocator (cmem) keeps FPC's
# heap, the one heaptrc watches
TESTFLAGS := $(COMMON) $(SYNAPSE_FLAGS) $(SRCPATH) -Futools/lib -Futests/support -B -Cr -Co -Ct -gh -gl -Xs- -dCHN_HEAPTRC \
             -Fu$(BUILD)/fpcunit -FU$(TUNITDIR) -FE$(TBINDIR) -Fi$(BUILD)
# FPCUnit rebuilt from Debian's fpc-source without optimisation, so that a
# failing assert's location names the test's own line (the prebuilt one
# loses the caller's frame); without fpc-source the prebuilt one is used.
FPCUNIT_SRC = /usr/share/fpcsrc/$(shell $(FPC) -iV)/packages/fcl-fpcunit/src

# The units: fpmake.pp is the one list (tools/units.sh reads it); its
# optional ones (the Synapse backend) build only with SYNAPSE_DIR.
UNITS    := $(shell bash tools/units.sh $(OSDIR)) $(if $(SYNAPSE_DIR),$(shell bash tools/units.sh --optional))
LIBSRC   := $(UNITS) $(wildcard src/*.inc src/*/*.inc src/*/$(OSDIR)/*.inc)
TOOLLIB  := $(wildcard tools/lib/*.pas)
EXAMPLES := $(wildcard examples/*.pas)
TOOLS    := $(wildcard tools/*.pas)
BENCHES  := $(wildcard bench/*.pas)
TESTUNITS := $(wildcard tests/Test*.pas)
PROGRAMS := $(EXAMPLES) $(TOOLS)
PROGBINS := $(addprefix $(BINDIR)/,$(basename $(notdir $(PROGRAMS))))
BENCHBINS := $(addprefix $(BINDIR)/,$(basename $(notdir $(BENCHES))))

# The flags the library was compiled with: when they change (SYNAPSE_DIR
# given or not) the units and programs start afresh - fpc does not see a
# changed -d, and a current units.stamp would keep the other build's units.
ifneq ($(UNITFLAGS),$(shell cat $(BUILD)/units.flags 2>/dev/null))
  $(shell rm -rf $(UNITDIR) $(TOOLUNITDIR) $(BUILD)/units.stamp $(PROGBINS) $(BENCHBINS); \
    mkdir -p $(BUILD); echo '$(UNITFLAGS)' > $(BUILD)/units.flags)
endif

.PHONY: all units examples tools test demo bench fuzz soak wintest clean check-fpc \
        install uninstall man doc cross crosstest mutate mutate-check

all: units $(PROGBINS) chn.lpk
examples: $(addprefix $(BINDIR)/,$(basename $(notdir $(EXAMPLES))))
tools: $(addprefix $(BINDIR)/,$(basename $(notdir $(TOOLS))))

# A build never installs anything itself (not even as root): it says how.
check-fpc:
	@command -v $(FPC) >/dev/null 2>&1 || { \
	  echo "fpc not found. Install it with:"; \
	  if [ "$$(id -u)" = 0 ]; then echo "  apt-get install -y $(DEB_PACKAGES)"; \
	  else echo "  sudo apt-get install -y $(DEB_PACKAGES)"; fi; exit 1; }

# Every library unit, compiled once by one fpc call on a generated unit
# that uses them all; fpc itself recompiles only what changed.
units: $(BUILD)/units.stamp
$(BUILD)/units.stamp: $(LIBSRC) fpmake.pp | check-fpc
	@mkdir -p $(UNITDIR) $(BINDIR)
	@# compiled units that "fpc -Fusrc prog.pas" left beside the sources
	@# would be taken as current and never reach $(UNITDIR)
	@if [ -n "$$(ls src/*/*.ppu src/*/*/*.ppu tools/lib/*.ppu 2>/dev/null)" ]; then \
	  echo "note: removing compiler output left in src/ or tools/lib/"; \
	  rm -f src/*/*.ppu src/*/*.o src/*/*.rsj src/*/*/*.ppu src/*/*/*.o src/*/*/*.rsj \
	    tools/lib/*.ppu tools/lib/*.o tools/lib/*.rsj; fi
	@$(if $(SYNAPSE_DIR),$(FPC) $(COMMON) $(SYNAPSE_FLAGS) -O2 -FU$(UNITDIR) -FE$(BINDIR) $(SYNAPSE_DIR)/synaser.pas >/dev/null;) true
	@{ echo 'unit chnall; interface uses'; \
	   echo '$(basename $(notdir $(UNITS)))' | sed 's/ /, /g'; \
	   echo '; implementation end.'; } > $(BUILD)/chnall.pas
	@echo "fpc src/*/*.pas"
	@$(FPC) $(UNITFLAGS) $(BUILD)/chnall.pas
	@# the tools/lib units were compiled against the library as it was: fpc
	@# checks a used unit only by the checksum of its interface, which can
	@# miss a change (an inline routine's body, a record seen through another
	@# unit), and a tool kept the old layout (chngate spun on a changed
	@# record); the programs make rebuilds compile them afresh
	@rm -rf $(TOOLUNITDIR)
	@touch $@

# The Lazarus package lists every unit of fpmake.pp (all OSes).
chn.lpk: fpmake.pp $(wildcard src/*.inc src/*/*.inc src/*/*/*.inc) tools/mklpk.sh tools/units.sh
	@bash tools/mklpk.sh

# Which sources each program depends on (from the uses clauses and the
# {$I} include files, transitively through src/ and tools/lib).
$(BUILD)/deps.mk: $(LIBSRC) $(TOOLLIB) $(PROGRAMS) $(BENCHES) tools/mkdeps.sh
	@mkdir -p $(BUILD)
	@bash tools/mkdeps.sh $(BINDIR) $(SRCDIRS) $(wildcard src/*/$(OSDIR)) tools/lib -- $(PROGRAMS) $(BENCHES) > $@.tmp && mv $@.tmp $@
-include $(BUILD)/deps.mk

# One program: its units are current (units.stamp, order only: a program
# is rebuilt when a source or include file it uses changed, see deps.mk),
# so fpc compiles the program (and any tools/lib unit it uses) and links.
$(PROGBINS) $(BENCHBINS): | $(BUILD)/units.stamp
	@mkdir -p $(TOOLUNITDIR)
	@echo "fpc $(filter %/$(notdir $@).pas,$(PROGRAMS) $(BENCHES))"
	@$(FPC) $(PROGFLAGS) $(filter %/$(notdir $@).pas,$(PROGRAMS) $(BENCHES))

# The runner's uses clause is generated from tests/Test*.pas, so adding a
# test unit needs no edit anywhere else. Units that need Unix as a whole
# (ptys) are listed here and built only there; single Unix-only tests are
# {$IFDEF UNIX} in their unit.
UNIX_TESTS := TestChnPty TestChnComVirtual TestChnTcpSer2net TestFT12Examples TestFaultCycling TestIec101Examples \
              TestIec101SlaveTool TestIec101Docs TestIec104Tools TestIec104Docs TestChnIecPointTable
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
	@# programs with the test flags (heaptrc): what they leave at exit is tested
	@for p in $(HEAPPROGS); do $(FPC) $(SOAKFLAGS) $$p >>$(BUILD)/test-build.log 2>&1 || { cat $(BUILD)/test-build.log; echo "0 passed, 1 failed"; exit 1; }; done
	@BUILD=$(BUILD) FPC=$(FPC) T="$(T)" bash tests/run.sh

# only the programs it runs: a first make demo builds the library
# and those, not every example
demo: $(addprefix $(BINDIR)/,df1sim df1echo df1read chndecode chngate iec101slave)
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
# programs make test also builds with the test flags into $(TBINDIR): the
# suite checks with heaptrc that they free everything at exit (usage
# errors too)
HEAPPROGS := examples/iec101master.pas examples/iec101slave.pas examples/df1write.pas tools/chntap.pas tools/df1sim.pas \
             tools/chndecode.pas tools/chngate.pas
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

# ARM Linux (docs/ARM.md): the cross compiler is built once into
# CROSS_CACHE (outside the repository; from Debian's fpc source package),
# the project into $(BUILD)/$(ARCH) with the usual flags.
ARCH ?=
CROSS_CACHE ?= $(if $(HOME),$(HOME),/tmp)/.cache/chn-cross
cross crosstest:
	@CROSS_CACHE='$(CROSS_CACHE)' BUILD='$(BUILD)/$(ARCH)' T='$(T)' SYNAPSE_DIR='$(SYNAPSE_DIR)' \
	  bash tools/cross.sh $(if $(filter cross,$@),build,test) '$(ARCH)'

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

# The library's version, written once (src/core/chnversion.inc)
CHNVERSION = $(shell sed -n "s/^'\(.*\)'$$/\1/p" src/core/chnversion.inc)

# The programs that are tools (docs/TOOLS.md, "Installed tools"): into
# $(PREFIX)/bin, each with a man page made from its --help and --version
# by Debian's help2man (without help2man the pages are left out, with a
# note). The other examples are demos of the API and stay in build/bin.
TOOL_PROGRAMS := df1sim chndecode chntap chnline chngate df1read df1write df1echo comraw waitany \
                 $(basename $(notdir $(wildcard examples/iec101master.pas examples/iec101slave.pas examples/plcconc.pas)))
INSTALL_BINDIR ?= $(PREFIX)/bin
INSTALL_MANDIR ?= $(PREFIX)/share/man/man1
# chngate's systemd unit (its example configuration goes to INSTALL_SRCDIR)
INSTALL_UNITFILEDIR ?= $(PREFIX)/lib/systemd/system
MANDIR := $(BUILD)/man

man: $(addprefix $(MANDIR)/,$(addsuffix .1,$(TOOL_PROGRAMS)))
$(MANDIR)/%.1: $(BINDIR)/%
	@mkdir -p $(MANDIR)
	@if command -v help2man >/dev/null 2>&1; then \
	  help2man -N --no-discard-stderr -s 1 -m 'Chn tools' -S 'Chn $(CHNVERSION)' \
	    -n "$$($< --help | sed -n '2,/^$$/p' | tr '\n' ' ' | sed 's/ ([^)]*)//g; s/[.:;].*//')" -o $@ $< || exit 1; \
	else echo "note: help2man not found (apt-get install help2man): no man page for $*"; fi

# The API reference from the interface comments, by Debian's pasdoc, as
# HTML in build/doc; a warning fails it (the suite checks that every
# library unit has its page: tests/packaging.sh).
DOCSRC := $(sort $(wildcard src/*/*.pas src/*/*/*.pas))
doc:
	@command -v pasdoc >/dev/null 2>&1 || { echo "pasdoc not found: apt-get install pasdoc"; exit 1; }
	@rm -rf $(BUILD)/doc; mkdir -p $(BUILD)/doc
	@pasdoc --format html --output $(BUILD)/doc --title 'Chn library $(CHNVERSION)' \
	  --include src/ $(addprefix --include ,$(sort $(dir $(DOCSRC)))) --define FPC --define UNIX --define LINUX \
	  --ignore-marker=- --write-uses-list --sort=structures,non-record-fields $(DOCSRC) >$(BUILD)/doc.log 2>&1 || { cat $(BUILD)/doc.log; exit 1; }
	@if grep -E '^(Warning|Error)' $(BUILD)/doc.log; then echo "make doc: pasdoc warnings (above)"; exit 1; fi
	@echo "API reference: $(BUILD)/doc/index.html ($(words $(DOCSRC)) units)"

# A Synapse build's units use synaser (and what it uses): a program built
# with plain fpc against the installed units needs them too, so the
# Synapse units this build compiled (those of $(UNITDIR) that are sources
# of SYNAPSE_DIR) are installed beside them; uninstall removes them with
# the folder. Synapse itself is not part of this project (docs/ChnCom.md).
SYNAPSE_INSTALL = n=0; for p in $(UNITDIR)/*.ppu; do u=$$(basename "$$p" .ppu); \
	  if [ -f '$(SYNAPSE_DIR)'/"$$u.pas" ] || [ -f '$(SYNAPSE_DIR)'/"$$u.pp" ]; then \
	    install -m 644 "$$p" "$$d/"; install -m 644 "$(UNITDIR)/$$u.o" "$$d/"; n=$$((n+1)); fi; done; \
	  if [ "$$n" = 0 ]; then echo "install: no Synapse units in $(UNITDIR) (SYNAPSE_DIR=$(SYNAPSE_DIR)): run make SYNAPSE_DIR=... first" >&2; exit 1; fi; \
	  echo "installed $$n Synapse units (synaser and what it uses) from $(SYNAPSE_DIR) beside them"

# (a unit without code, such as ChnPorts, has no object file)
install: units $(addprefix $(BINDIR)/,$(TOOL_PROGRAMS)) man
	@set -e; d='$(DESTDIR)$(INSTALL_UNITDIR)'; s='$(DESTDIR)$(INSTALL_SRCDIR)'; \
	b='$(DESTDIR)$(INSTALL_BINDIR)'; m='$(DESTDIR)$(INSTALL_MANDIR)'; \
	mkdir -p "$$d" "$$s/src" "$$b"; \
	for u in $(basename $(notdir $(UNITS))); do l=$$(echo $$u | tr A-Z a-z); \
	  install -m 644 $(UNITDIR)/$$u.ppu "$$d/$$l.ppu"; \
	  if [ -f $(UNITDIR)/$$u.o ]; then install -m 644 $(UNITDIR)/$$u.o "$$d/$$l.o"; fi; done; \
	$(if $(SYNAPSE_DIR),$(SYNAPSE_INSTALL);) \
	for f in $(wildcard src/*.inc src/README.md src/*/*.pas src/*/*.inc src/*/*/*.pas src/*/*/*.inc); do \
	  install -D -m 644 "$$f" "$$s/$$f"; done; install -m 644 chn.lpk COPYING COPYING.LGPL "$$s/"; \
	for p in $(TOOL_PROGRAMS); do install -m 755 $(BINDIR)/$$p "$$b/$$p"; \
	  if [ -f $(MANDIR)/$$p.1 ]; then mkdir -p "$$m"; install -m 644 $(MANDIR)/$$p.1 "$$m/$$p.1"; fi; done; \
	install -m 644 tools/chngate.conf "$$s/chngate.conf"; \
	mkdir -p '$(DESTDIR)$(INSTALL_UNITFILEDIR)'; \
	sed 's|@PREFIX@|$(PREFIX)|g' tools/chngate.service > '$(DESTDIR)$(INSTALL_UNITFILEDIR)/chngate.service'; \
	echo "installed units in $$d, sources in $$s, tools in $$b, man pages in $$m," \
	  "the gateway's example configuration $$s/chngate.conf and systemd unit $(INSTALL_UNITFILEDIR)/chngate.service"; \
	$(if $(DESTDIR),true,$(INSTALL_HINT))

# After an install to a prefix fpc.cfg does not search (asked of fpc
# itself, tools/fpcsearches.sh): the -Fu a program's fpc call needs. Not
# with DESTDIR (a package's staging folder, not where the units will be).
INSTALL_HINT = if ! bash tools/fpcsearches.sh '$(FPC)' '$(INSTALL_UNITDIR)'; then \
	  echo "note: fpc does not search $(INSTALL_UNITDIR) (/etc/fpc.cfg): compile your programs with"; \
	  echo "  fpc -Fu$(INSTALL_UNITDIR) yourprogram.pas"; \
	  echo "or put that -Fu line into ~/.fpc.cfg (PREFIX=/usr or PREFIX=\$$HOME/.fppkg need none)"; fi

uninstall:
	rm -rf '$(DESTDIR)$(INSTALL_UNITDIR)' '$(DESTDIR)$(INSTALL_SRCDIR)'
	rm -f $(foreach p,$(TOOL_PROGRAMS),'$(DESTDIR)$(INSTALL_BINDIR)/$(p)' '$(DESTDIR)$(INSTALL_MANDIR)/$(p).1') \
	  '$(DESTDIR)$(INSTALL_UNITFILEDIR)/chngate.service'

clean:
	rm -rf $(BUILD)
