# wrlayer: FEM-calibrated Prandtl surface layers for wheel/rail contact.
# Every target bootstraps .venv (and the system libraries the gmsh/vtk wheels link against) when missing or stale.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
OUT ?= out
export PYVISTA_OFF_SCREEN := true
export MPLBACKEND := Agg

.PHONY: all setup test simulate wear calibrate bench bench-full stress plots clean distclean

all: test

setup: $(STAMP)

# Debian packages providing the shared libraries the gmsh and vtk wheels need (soname prefix -> package).
SYSLIBS := libGLU.so:libglu1-mesa libGL.so:libgl1 libOpenGL.so:libopengl0 libGLX.so:libglx0 libEGL.so:libegl1 \
  libOSMesa.so:libosmesa6 libXrender.so:libxrender1 libXcursor.so:libxcursor1 libXfixes.so:libxfixes3 \
  libXext.so:libxext6 libXft.so:libxft2 libXinerama.so:libxinerama1 libX11.so:libx11-6 libxcb.so:libxcb1 \
  libfontconfig.so:libfontconfig1 libfreetype.so:libfreetype6 libgomp.so:libgomp1 libXi.so:libxi6 libSM.so:libsm6 \
  libICE.so:libice6 libXt.so:libxt6 libz.so:zlib1g libpng16.so:libpng16-16 libexpat.so:libexpat1

$(STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test,fast,cluster]'
	@missing=$$(for so in $$(find $(VENV) -name 'libgmsh.so*' -o -name 'libvtkRenderingOpenGL2*.so*' | head -5); do \
	    ldd $$so 2>/dev/null | awk '/not found/{print $$1}'; done | sort -u); \
	if [ -n "$$missing" ]; then \
	  pkgs=""; for lib in $$missing; do for pair in $(SYSLIBS); do \
	    case "$$lib" in "$${pair%%:*}"*) pkgs="$$pkgs $${pair##*:}";; esac; done; done; \
	  echo "installing system libraries for gmsh/vtk:$$pkgs (missing: $$missing)"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$pkgs libosmesa6 >/dev/null; \
	fi
	$(PY) -c "import gmsh, skfem, pyvista, meshio; gmsh.initialize(); gmsh.finalize()"
	@touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q -n 2 tests

simulate: $(STAMP)
	$(PY) -m contact simulate-all scenes --out $(OUT)/simulate --plots

# Wear simulation example (S1002 on 60E1, a small load collective, 3000 km): profiles, table and pictures.
wear: $(STAMP)
	$(PY) -m contact wear scenes/wear/s1002_60e1.toml --out $(OUT)/wear

calibrate: $(STAMP)
	$(PY) -m calibration run calibration/configs/default.toml --out $(OUT)/calibration

bench: $(STAMP)
	$(VENV)/bin/pip install -q -e '.[bench]'
	$(PY) -m benchmarks --quick --out $(OUT)/bench

bench-full: $(STAMP)
	$(VENV)/bin/pip install -q -e '.[bench]'
	$(PY) -m benchmarks --full --out $(OUT)/bench

stress: $(STAMP)
	$(PY) -m benchmarks.stress --full --out $(OUT)/stress

plots: $(STAMP)
	$(PY) -m meshes plots --out $(OUT)/plots

clean:
	rm -rf $(OUT) .pytest_cache .hypothesis
	find . -name __pycache__ -type d -prune -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV) *.egg-info
