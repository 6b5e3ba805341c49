# ProgSurf: shortcuts for the README's two commands (./demo.sh, ./test.sh) and the benchmark.
.PHONY: install demo test bench

install:
	./install.sh

demo:
	./demo.sh

test:
	./test.sh

# Benchmarks against FreeCAD's Surface::Filling / GeomFillSurface (issue 8), and quality on 108
# hand-like sketches in G0 and G1 (issue 16; benchmarks/quality.py): ~20 min on 2 cores.
bench: install
	mkdir -p out/bench
	.venv/bin/python benchmarks/run.py --out out/bench
