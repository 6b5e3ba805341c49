# ProgSurf: the two commands of the README, and the install step they share.
.PHONY: install demo test

install:
	./install.sh

# The main job on a bundled example: strokes in, STEP shell, picture and report out.
demo: install
	mkdir -p out
	.venv/bin/python -m ProgSurf build examples/clean4.xyz -o out/demo.step \
		--png out/demo.png --report out/demo.json

# The whole suite, three levels (core+app pytest, freecadcmd -t TestProgSurfApp, GUI under Xvfb).
test: install
	.venv/bin/python tests/run_suite.py
