#!/usr/bin/env bash
# Regenerates PropulsionTopologyDictionary.json from the FPP model with F´'s own tool,
# `fpp-to-dict`, from the `fprime-fpp` package on PyPI (`pip install fprime-fpp==3.4.0`).
# CI does not run this: the generated dictionary is committed, and the tests read it.
set -euo pipefail
cd "$(dirname "$0")"
command -v fpp-to-dict >/dev/null || { echo "fpp-to-dict not found: pip install fprime-fpp==3.4.0" >&2; exit 1; }
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
fpp-to-dict -i FwStub.fpp -p 1.0.0 -f 3.4.3 -d "$out" Propulsion.fpp
mv "$out/LanderTopologyDictionary.json" PropulsionTopologyDictionary.json
echo "wrote $(pwd)/PropulsionTopologyDictionary.json"
