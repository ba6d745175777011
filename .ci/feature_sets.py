#!/usr/bin/env python3
"""Lists the crates that two of CI's cargo commands would build with different features.

Cargo unifies a dependency's features over the packages a command selects, so `pip install
./python` (rollphase-python alone), the test build without the default features and the one
with them could each build serde, glam, wgpu, ... differently, and then everything above them
again. crates/workspace-hack (the core's dependencies) and the root's dev-dependencies (the GPU
stack) pin the union; this script checks that they still do, from `cargo tree` alone (seconds,
nothing is compiled). Exit 1, naming the crates and their feature sets, when a pin is missing.
"""
import subprocess
import sys

# What each of .ci/run's builds selects, and which edges it follows.
BUILDS = {
    "cargo test --all-targets (default features)": ["-e", "normal,build,dev"],
    "cargo build --no-default-features --all-targets": [
        "-e", "normal,build,dev", "--no-default-features", "-p", "rollphase"],
    "the binary without default features (no dev-dependencies)": [
        "-e", "normal,build", "--no-default-features", "-p", "rollphase"],
    # The README's main job: the binary alone, without the dev-dependencies' features.
    "cargo run (the binary, no dev-dependencies)": ["-e", "normal,build", "-p", "rollphase"],
    "pip install ./python (rollphase-python alone)": [
        "-e", "normal,build", "-p", "rollphase-python"],
}


# Packages whose features are what the builds differ by.
EXPECTED = {"rollphase", "rollphase-viewer"}


def features(args):
    out = subprocess.run(
        ["cargo", "tree", "-f", "{p} [{f}]", "--prefix", "none", *args],
        capture_output=True, text=True, check=True).stdout
    found = {}
    for line in out.splitlines():
        line = line.replace(" (*)", "").strip()
        if " [" not in line:
            continue
        name, feats = line.rsplit(" [", 1)
        # A crate built for the host and for the target shows twice; both must agree.
        found.setdefault(name.strip(), set()).add(feats.rstrip("]"))
    return found


def main():
    sets = {build: features(args) for build, args in BUILDS.items()}
    differ = 0
    crates = sorted(set().union(*(s.keys() for s in sets.values())))
    for crate in crates:
        if crate.split(" ")[0] in EXPECTED:
            continue
        seen = {b: frozenset(s[crate]) for b, s in sets.items() if crate in s}
        if len(seen) > 1 and len(set(seen.values())) > 1:
            differ += 1
            print(crate)
            for build, feats in seen.items():
                print(f"    {build}: {' | '.join(sorted(feats))}")
    if differ:
        print(f"{differ} crates are built with different features by CI's commands: pin the "
              "union in crates/workspace-hack (the core's dependencies) or the root's "
              "dev-dependencies (the GPU stack)", file=sys.stderr)
        return 1
    print(f"feature sets agree across {len(BUILDS)} builds ({len(crates)} crates)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
