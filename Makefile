# ProgSurf: shortcuts for the README's two commands (./demo.sh, ./test.sh) and the benchmark.
.PHONY: install demo test bench

install:
	./install.sh

demo:
	./demo.sh

test:
	./test.sh

# Benchmarks against FreeCAD's Surface::Filling / GeomFillSurface (issue 8); ~7 min on 2 cores.
bench: install
	mkdir -p out/bench
	.venv/bin/python benchmarks/run.py --out out/bench
