# debrisfoam: every target installs what it needs itself (idempotent).
SHELL   := /bin/bash
PYTHON  ?= python3
VENV    := .venv
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
# make case-1debris CELL=0.01 runs the 1-debris scene finer (finest cell size in metres);
# COUPLING=two-way runs it coupled (overset six-DoF bodies) instead of the planner's choice
# (one-way for this scene: the flow once, the container carried through its record).
CELL     ?=
COUPLING ?=
OUT      ?= runs/1debris$(if $(COUPLING),-$(COUPLING),)
CASE_SET := $(if $(CELL),--set mesh.cell_size_m=$(CELL),) $(if $(COUPLING),--set run.debris_coupling=$(COUPLING),)

.PHONY: approach ensemble-flow-pair prototype-1debris design-street design-1debris forcing-variants help venv openfoam test test-all test-fast docs-check case-1debris case-layouts results-layouts compare-coupling sweep speed-error speed-error-debris stability flume-as-built flume-2d face-splash wet-bed synthetic-study contact-law results-1debris ensemble-1debris ensemble-flows spreading scene-doc catalogue-doc bench bench-transport clean

help:
	@echo "make help                   this list: every target"
	@echo "make openfoam               OpenFOAM v1912 from Debian's openfoam package, only when it is missing (needs root)"
	@echo "make venv                   the Python environment only (.venv, the package installed editable)"
	@echo "make case-1debris [CELL=m] [COUPLING=two-way]  the study's 1-debris scene, end to end (one-way: about 5 min on 2 idle cores; two-way: about 2 h)"
	@echo "make results-1debris        after it: its table, plots and summary to docs/results/case-1debris/"
	@echo "make prototype-1debris      the 1-debris scene at 40:1 one-way (about as long as case-1debris), beside the lab run Froude-scaled (docs/results/prototype-1debris/)"
	@echo "make design-street          debrisfoam design on the street scene: 3 flows and 2000 realisations (runs/design-street, docs/results/design-street)"
	@echo "make design-1debris         debrisfoam design on the 1-debris scene: its flow and 200 realisations (runs/design-1debris, docs/results/design-1debris)"
	@echo "make ensemble-1debris [N=200] the 1-debris flow once, N perturbed starts through it (runs/ensemble-1debris, docs/results/ensemble-1debris)"
	@echo "make spreading              one-way ensembles of the 1-debris scene and the 3- and 6-container layouts, their tracks against measured spreading (docs/results/spreading)"
	@echo "make case-layouts           the study's four debris layouts one-way (about 27 min on 2 idle cores), then results-layouts"
	@echo "make results-layouts        after it: the layouts side by side to docs/results/layouts/"
	@echo "make sweep SWEEP=mesh-study a sweep from cases/sweeps/ (runs/sweeps/<name>; run again to resume)"
	@echo "make speed-error            mesh study + hand-made baseline, then the speed-against-error report (about 15 min; docs/results/speed-error/)"
	@echo "make speed-error-debris     mesh study with one container to its impact, then its report"
	@echo "make compare-coupling       the short flume to the first strike two-way and one-way on one mesh, side by side (about 30 min)"
	@echo "make stability              the hard cases of cases/hard/ (about 2 h), then their stability table"
	@echo "make test                   the default test suite, real OpenFOAM runs included (about 8 min on 2 cores; installs the venv and OpenFOAM first)"
	@echo "make test-all               every test, the slow ones too (about 45 min on 2 idle cores)"
	@echo "make test-fast              the Python tests without OpenFOAM and without the slow ones"
	@echo "make clean                  remove the venv and build files"
	@echo "make docs-check             the docs: links resolve, no history, README at most 800 words, docs/*.md at most 15,000, make help complete, figures the planner gives"
	@echo "make ensemble-flows         the ensemble through RANS with a sill, the flume as built, the posts alone and the WG2-read bed drag (about 1 h; docs/results/ensemble-1debris-*/)"
	@echo "make ensemble-flow-pair     the ensemble through a second mesh's flow: Table 2 with the flow's own uncertainty (docs/results/ensemble-flow-pair/)"
	@echo "make flume-2d               the study's flume as a 2D centreline strip, RANS at 2 cm and 1 cm cells, each with and without the 5 cm sill: how much the 3D arrivals owe to 4 cm cells (docs/results/flume-centreline-2d/)"
	@echo "make face-splash            the water at the column's face at 4 cm cells and with 2 cm cells at the face (laminar and RANS), against the study's load points 0.16-0.50 m; the front's speed over 0.5 m reaches (about 30 min; docs/results/face-splash/)"
	@echo "make flume-as-built         the gate's sill and opening, the wet bed's depth, the column's position, the bed drag's coefficient: arrivals one change at a time and the sill and opening together (about 12 min; docs/results/flume-as-built/)"
	@echo "make wet-bed                the bore against Stoker's wet-bed solution, laminar and RANS (about 40 min; docs/results/wet-bed/)"
	@echo "make synthetic-study        the study's SDOF/MDOF/ASCE analysis on 22 synthetic records"
	@echo "make scene-doc              docs/scene.md, the scene reference, from the schema"
	@echo "make catalogue-doc          docs/catalogue.md, the debris and column catalogue, from its data"
	@echo "make contact-law            calibrate the contact law on Table 2 (22 impacts), check it on Table 1 (docs/results/contact-law/)"
	@echo "make bench                  benchmarks (figures go to benchmarks/*.md)"
	@echo "make bench-transport        one-way transport and ensemble benchmarks (benchmarks/transport.md, ensemble.md)"
	@echo "make approach [OUT=runs/1debris]  after make case-1debris: the strike speed against the record's cell size near the column, its frame rate and the forcing near the face, with the force budget (docs/results/approach/)"
	@echo "make forcing-variants       after make case-1debris: the one-way forcing's variants through its record (benchmarks/forcing_variants.md)"

venv: $(STAMP)
$(STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV) 2>/dev/null || { \
	  rm -rf $(VENV); \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "Installing python3-venv (Debian package; $(PYTHON) -m venv needs it)..."; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >/dev/null && \
	    $(PYTHON) -m venv $(VENV); \
	  else \
	    echo "$(PYTHON) -m venv failed: on Debian or Ubuntu run 'sudo apt-get install python3-venv', then make again" >&2; false; \
	  fi; }
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	@touch $@

# OpenFOAM v1912 from Debian's `openfoam` package, only when it is missing.
openfoam:
	@if command -v overInterDyMFoam >/dev/null 2>&1; then \
	  echo "OpenFOAM found: $$(command -v overInterDyMFoam)"; \
	elif [ "$$(id -u)" = 0 ]; then \
	  echo "Installing OpenFOAM (Debian package openfoam)..."; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openfoam >/dev/null; \
	  command -v overInterDyMFoam >/dev/null || { echo "OpenFOAM install failed: overInterDyMFoam not on PATH" >&2; exit 1; }; \
	else \
	  echo "OpenFOAM is missing and this is not root: run 'sudo apt-get install openfoam', then make again" >&2; exit 1; \
	fi

# The Python tests two at a time (pytest-xdist, one per core), then the OpenFOAM tests two files at
# a time: a tiny case's two MPI ranks keep a core busy only part of the time (meshing, decomposing
# and post-processing are serial, and the ranks yield while they wait), so two files side by side
# fill both cores; a file's tests stay on one worker and share its fixtures. Tests marked slow
# (minutes each: the contact law's calibration, the wheel's install, the longer OpenFOAM cases) are
# left to test-all.
OPENFOAM_TESTS = -n 2 --dist loadfile
test: venv openfoam
	$(VENV)/bin/ruff check .
	$(PY) -m pytest -q -n 2 -m "not openfoam and not slow"
	$(PY) -m pytest -q $(OPENFOAM_TESTS) -m "openfoam and not slow"

# Every test, the slow ones included (about 45 min on 2 idle cores).
test-all: venv openfoam
	$(VENV)/bin/ruff check .
	$(PY) -m pytest -q -n 2 -m "not openfoam"
	$(PY) -m pytest -q $(OPENFOAM_TESTS) -m openfoam

test-fast: venv
	$(PY) -m pytest -q -m "not openfoam and not slow"

# The docs checked like code (tests/test_docs.py, seconds, no OpenFOAM): every relative link
# resolves, README and docs/*.md say what is true now (history is CHANGELOG.md's), the README
# stays a two-minute read and docs/*.md within 15,000 words, `make help` lists every target, and
# the figures the planner can recompute (cells, cost factors) agree.
docs-check: venv
	$(PY) -m pytest -q tests/test_docs.py

case-1debris: venv openfoam
	$(VENV)/bin/debrisfoam case cases/1debris.yaml -o $(OUT) $(CASE_SET)

# The study's 1-debris scene at 40:1 (cases/prototype-1debris.yaml), run one-way, then set beside the
# lab run Froude-scaled (runs/1debris, made first when missing): docs/results/prototype-1debris/.
LAB_RUN   ?= runs/1debris
PROTO_RUN ?= runs/prototype-1debris
prototype-1debris: venv openfoam
	@test -f $(LAB_RUN)/results/summary.json || $(VENV)/bin/debrisfoam case cases/1debris.yaml -o $(LAB_RUN)
	$(VENV)/bin/debrisfoam case cases/prototype-1debris.yaml -o $(PROTO_RUN) --yes
	$(VENV)/bin/debrisfoam report scale $(LAB_RUN) $(PROTO_RUN) -o docs/results/prototype-1debris --force

# After make case-1debris: its table beside the study's figures, its plots and summary, to
# docs/results/case-1debris/ (the page the README's table comes from).
results-1debris: venv
	$(VENV)/bin/debrisfoam report case $(OUT) -o docs/results/case-1debris$(if $(COUPLING),-$(COUPLING),) --force

# The study's four debris layouts (cases/sweeps/debris-layouts.yaml), each one-way (run.debris_coupling
# auto): the flow without the bodies, then the bodies carried through its record; run again to resume.
# A failed member does not stop the page: it is listed there with its error and log.
LAYOUTS_OUT ?= runs/sweeps/debris-layouts
case-layouts: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/debris-layouts.yaml -o $(LAYOUTS_OUT)
	$(MAKE) results-layouts

# After make case-layouts: gauges and column force overlaid, tracks, strikes and contacts per layout,
# to docs/results/layouts/ (report.md, tables, plots).
results-layouts: venv
	$(VENV)/bin/debrisfoam report layouts $(LAYOUTS_OUT) -o docs/results/layouts --force

# make ensemble-1debris [N=200]: the 1-debris scene's one-way flow once (about 5 min of interFoam on
# 2 cores; reused when run again), then N realisations of perturbed starts through it (docs/ensembles.md).
# ENS_NAME and ENS_SET run another flow, e.g. 4 cm cells at the column too (docs/ensembles.md):
#   make ensemble-1debris ENS_NAME=ensemble-1debris-4cm ENS_SET="--set mesh.column_approach_cell_size_m=null"
N ?= 200
ENS_NAME ?= ensemble-1debris
ENS_SET ?=
ensemble-1debris: venv openfoam
	$(VENV)/bin/debrisfoam ensemble cases/1debris.yaml -n $(N) -o runs/$(ENS_NAME) --force $(ENS_SET)
	mkdir -p docs/results/$(ENS_NAME)
	cp runs/$(ENS_NAME)/report.md runs/$(ENS_NAME)/ensemble.json runs/$(ENS_NAME)/histograms.png \
	   runs/$(ENS_NAME)/envelope.png docs/results/$(ENS_NAME)/

# make ensemble-flows: the ensemble above through the four other flows the bed-friction
# page compares (docs/bed-friction.md): RANS with the 5 cm sill, the flume as built (sill and 0.9 m
# opening), the 0.9 m opening alone, and the bed drag's coefficient read from WG2 (c = 3.2). About 1 h on 2 idle cores
# (the RANS flow about 30 min, each laminar one about 10).
ensemble-flows: venv openfoam
	$(MAKE) ensemble-1debris ENS_NAME=ensemble-1debris-rans-sill ENS_SET="--set reservoir.sill_height_m=0.05 --set reservoir.depth_m=0.35 --set fluids.turbulence=kOmegaSST --set mesh.wet_bed_cells=4"
	$(MAKE) ensemble-1debris ENS_NAME=ensemble-1debris-as-built ENS_SET="--set reservoir.sill_height_m=0.05 --set reservoir.depth_m=0.35 --set reservoir.opening_width_m=0.9"
	$(MAKE) ensemble-1debris ENS_NAME=ensemble-1debris-posts ENS_SET="--set reservoir.opening_width_m=0.9"
	$(MAKE) ensemble-1debris ENS_NAME=ensemble-1debris-c-wg2 ENS_SET="--set bed.friction_calibration=3.2"

# make ensemble-flow-pair: the ensemble above (made first when missing) and the same starts through a second
# mesh's flow (4 cm cells at the column too: runs/ensemble-1debris-4cm, about 3 min of interFoam), then the
# study comparison with the flow's own uncertainty to docs/results/ensemble-flow-pair/ (docs/ensembles.md).
ensemble-flow-pair: venv openfoam
	@test -f runs/ensemble-1debris/ensemble.json || $(MAKE) ensemble-1debris
	$(MAKE) ensemble-1debris ENS_NAME=ensemble-1debris-4cm ENS_SET="--set mesh.column_approach_cell_size_m=null"
	$(VENV)/bin/debrisfoam report flow-pair runs/ensemble-1debris runs/ensemble-1debris-4cm \
	  -o docs/results/ensemble-flow-pair --force

# make design-street: `debrisfoam design` on cases/design-street.yaml (a 20-ft container onto a
# 1.0 m RC column, three inundation cases): the three one-way flows (93k-122k cells, reused when run
# again) and 2000 realisations, then the page (design.md, design.json, exceedance.png; the per-realisation
# design.csv stays in runs/) to docs/results/design-street/ (docs/design.md gives the measured time).
design-street: venv openfoam
	$(NICE) $(VENV)/bin/debrisfoam design cases/design-street.yaml -o runs/design-street --force --yes
	mkdir -p docs/results/design-street
	cp runs/design-street/design.md runs/design-street/design.json runs/design-street/exceedance.png \
	   docs/results/design-street/

# make design-1debris: `debrisfoam design` on the study's 1-debris scene at lab scale (its one-way flow,
# reused when run again, and 200 realisations), the page to docs/results/design-1debris/.
design-1debris: venv openfoam
	$(NICE) $(VENV)/bin/debrisfoam design cases/1debris.yaml -n 200 -o runs/design-1debris --force --yes
	mkdir -p docs/results/design-1debris
	cp runs/design-1debris/design.md runs/design-1debris/design.json runs/design-1debris/exceedance.png \
	   docs/results/design-1debris/

# make spreading: one-way ensembles of the 1-debris scene (SPREAD_N=200) and the 3x1, 1x3 and 2x3
# layouts (SPREAD_LAYOUT_N=100 each), then their tracks against Goseberg et al. 2016's measured spreading
# and the ASCE 7-22 6.11.5.1 envelopes (docs/results/spreading/). Each ensemble runs its scene's flow into
# runs/spreading/<scene>/flow once (about 4-5 min of interFoam each on 2 idle cores) and reuses it when run
# again; a finished one-way case of the same scene copied there serves too (runs/ensemble-1debris/flow, or
# a member of make case-layouts in runs/sweeps/debris-layouts/<id>/). The study's fit is left out
# (--no-study-fit): the page reads the tracks only.
SPREAD_N        ?= 200
SPREAD_LAYOUT_N ?= 100
SPREAD_SCENES   := 1debris:$(SPREAD_N) 3debris-3x1:$(SPREAD_LAYOUT_N) 3debris-1x3:$(SPREAD_LAYOUT_N) 6debris-2x3:$(SPREAD_LAYOUT_N)
spreading: venv openfoam
	@set -e; for spec in $(SPREAD_SCENES); do scene=$${spec%%:*}; n=$${spec##*:}; \
	  $(NICE) $(VENV)/bin/debrisfoam ensemble cases/$$scene.yaml -n $$n -o runs/spreading/$$scene --force \
	    --no-study-fit --batch-size 50; \
	done
	$(VENV)/bin/debrisfoam report spreading $(foreach s,$(SPREAD_SCENES),runs/spreading/$(firstword $(subst :, ,$(s)))) \
	  -o docs/results/spreading --force

# make sweep SWEEP=mesh-study [EXECUTOR=dask]: cases/sweeps/$(SWEEP).yaml -> runs/sweeps/<name>
SWEEP    ?= mesh-study
EXECUTOR ?= local
sweep: venv openfoam
	$(VENV)/bin/debrisfoam sweep cases/sweeps/$(SWEEP).yaml --executor $(EXECUTOR)

# The mesh study, the hand-made baseline (uniform cells, whole flume), then the report in
# runs/sweeps/mesh-study/report/. Both sweeps resume; a failed member does not stop the report.
# NICE="nice -n 15" runs the sweeps at low priority on a shared machine.
NICE ?=
speed-error: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/mesh-study.yaml
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/mesh-study-hand.yaml
	$(VENV)/bin/debrisfoam report speed-error runs/sweeps/mesh-study --baseline runs/sweeps/mesh-study-hand -o docs/results/speed-error --force

# The mesh study with one container (past its first impact on the column), then its report in
# docs/results/speed-error-debris/ (about 2.7 h of solver CPU time on 2 cores: 33, 61 and 68 min measured
# at 4, 3.5 and 3 cm; run again to resume).
speed-error-debris: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/debris-mesh-study.yaml
	$(VENV)/bin/debrisfoam report speed-error runs/sweeps/debris-mesh-study -o docs/results/speed-error-debris --force

# One-way against two-way: the short flume (cases/hard/short-flume.yaml: the study's flume,
# impoundment and container, the column at x = 3.0 m) to just past the first strike, run
# two-way (overset, about 25 min) and one-way (about 3 min) on the same background mesh, then
# the tracks' difference, the strikes and the cost side by side in docs/results/coupling/.
# A finished run is reused (run it again to resume); runs/coupling/two-way is the 4 cm member of
# make speed-error-debris, which a copy of that member serves. Another scene:
#   make compare-coupling COMPARE_SCENE=cases/1debris.yaml COMPARE_SET="--set run.end_time_s=2.5" \
#     COMPARE_NAME=coupling-1debris-3cm
# (the study's own layout on its default mesh to just past the strike: 31 min two-way, 4 min one-way;
# docs/results/coupling-1debris at 4 cm throughout: add --set mesh.column_approach_cell_size_m=null).
COMPARE_SCENE ?= cases/hard/short-flume.yaml
COMPARE_SET   ?= --set run.end_time_s=2.1
COMPARE_NAME  ?= coupling
compare-coupling: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam case $(COMPARE_SCENE) $(COMPARE_SET) --set run.debris_coupling=two-way -o runs/$(COMPARE_NAME)/two-way
	-$(NICE) $(VENV)/bin/debrisfoam case $(COMPARE_SCENE) $(COMPARE_SET) --set run.debris_coupling=one-way -o runs/$(COMPARE_NAME)/one-way
	@# a run that stopped early is post-processed as far as it got and compared up to there (the page
	@# says so); a summary older than the run's record (run.json) is from an earlier stop and is redone
	-@for r in two-way one-way; do test runs/$(COMPARE_NAME)/$$r/results/summary.json -nt runs/$(COMPARE_NAME)/$$r/run.json || \
	  $(VENV)/bin/debrisfoam post --tables-only runs/$(COMPARE_NAME)/$$r; done
	$(VENV)/bin/debrisfoam report coupling runs/$(COMPARE_NAME)/one-way runs/$(COMPARE_NAME)/two-way --drag-scan --allow-stopped -o docs/results/$(COMPARE_NAME) --force

# The hard cases (cases/hard/, about 2 h on 2 cores), then their table in docs/stability.md.
stability: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/hard-cases.yaml
	$(VENV)/bin/debrisfoam report stability runs/sweeps/hard-cases -o runs/sweeps/hard-cases/stability.md --force

# The bore against Stoker's wet-bed dam break: cases/sweeps/wet-bed.yaml (13 frictionless 2D members,
# laminar and RANS, the wet bed one cell layer or six, h1/h0 0.0375-0.2, 2 cm to 5 mm cells; about 40 min
# on 2 idle cores, 22 of them the 5 mm member; run again to resume), then the page docs/results/wet-bed/.
wet-bed: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/wet-bed.yaml
	$(VENV)/bin/debrisfoam report bore runs/sweeps/wet-bed -o docs/results/wet-bed --force

# The flume as built: cases/sweeps/flume-as-built.yaml (16 hydrodynamic members, one change each from
# cases/nodebris.yaml; about 12 min on 2 idle cores; run again to resume), then docs/results/flume-as-built/.
flume-as-built: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/flume-as-built.yaml
	$(VENV)/bin/debrisfoam report flume runs/sweeps/flume-as-built -o docs/results/flume-as-built --force

# The 2D centreline flume at 2 cm and 1 cm cells (cases/sweeps/flume-centreline-2d.yaml: RANS, each with and
# without the 5 cm sill), then docs/results/flume-centreline-2d/.
flume-2d: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/flume-centreline-2d.yaml
	$(VENV)/bin/debrisfoam report flume runs/sweeps/flume-centreline-2d -o docs/results/flume-centreline-2d --force

# Splash-up at the column's face (cases/sweeps/face-splash.yaml: the scene as shipped, and 2 cm cells in a box
# at the face laminar and RANS, over 3 s; 33 min of interFoam on 2 cores shared with an ensemble for most of it,
# the planner's estimate 29 min), then docs/results/face-splash/.
face-splash: venv openfoam
	-$(NICE) $(VENV)/bin/debrisfoam sweep cases/sweeps/face-splash.yaml
	$(VENV)/bin/debrisfoam report flume runs/sweeps/face-splash -o docs/results/face-splash --force

synthetic-study: venv
	$(VENV)/bin/debrisfoam analytical study -o docs/results/synthetic-study --force

# docs/scene.md, the scene reference, from the schema itself (a test checks it is current)
scene-doc: venv
	$(VENV)/bin/debrisfoam schema --markdown > docs/scene.md

catalogue-doc: venv
	$(VENV)/bin/debrisfoam catalogue --markdown > docs/catalogue.md

contact-law: venv
	$(VENV)/bin/debrisfoam analytical contact-law -o docs/results/contact-law --force

bench: venv
	$(PY) benchmarks/bench_analytical.py
	$(PY) benchmarks/bench_preview.py

# One-way transport (benchmarks/transport.md) and ensembles through one flow
# (benchmarks/ensemble.md: runs the 1-debris and 2x3 ensembles, their flows once, about 15 min).
bench-transport: venv openfoam
	$(NICE) $(PY) benchmarks/bench_transport.py
	$(NICE) $(PY) benchmarks/bench_ensemble.py

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info

# After make case-1debris: the container through its flow record under each forcing variant
# (drag per axis or along the flow, the Munk moment, three drag coefficients), the table
# docs/one-way.md quotes.
# The study's own flows (runs/approach-*, orchestrator/studies/approach_report.py STUDY_RUNS) are
# read when present; each missing one is named on the page with the command that makes it.
approach: venv
	$(VENV)/bin/debrisfoam report approach $(OUT) --runs runs -o docs/results/approach --force

forcing-variants: venv
	$(VENV)/bin/debrisfoam report forcing-variants $(OUT) -o benchmarks/forcing_variants.md --force
