#!/usr/bin/env bash
# Regenerates every image of the README and the user guide from the current code, in place:
#   docs/figures/NAME.png   each paper figure at full size (`rollphase figure NAME`)
#   docs/render/*.png       headless frames of the presets the guide shows
#   docs/render/app.png     the app's window (under Xvfb when there is no display)
#   docs/lessons/*.png      each lesson's window at a key moment
#   docs/accuracy/, docs/stiff/   the benchmark plots and tables
#   docs/plot-data/lesson-*/   the CSVs of the lessons' α and m/m0 sweeps (--plot-data)
#   docs/app-sweeps/        the app's measuring sweeps: screenshots and their plot data
#   docs/presentation/      each lesson on a projector, and class mode
#   docs/python/fig3d.png, fig4e.png   the Python module's figures (docs/python/paper_figures.py)
#   docs/experiments/*.png   the printed sphere's predicted paths and the tracked run, folded
#   docs/design/*.png        the designed sphere's orbit diagram and the printed sphere's
#   docs/bodies/*.png        several bodies on one ramp: which one stops, the doubling side by side
# Run from anywhere: bash docs/images.sh. Takes a few minutes on 2 cores without a GPU.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release
bin="$PWD/target/release/rollphase"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

for name in $("$bin" figure --list | awk 'NF { print $1 }'); do
    "$bin" figure "$name" --out "$tmp/figures" > /dev/null
    cp "$tmp/figures/$name/figure.png" "docs/figures/$name.png"
done

# A frame of a preset after `frames` frames at 960×540 (the README's image is the settled orbit).
frame() {
    local preset="$1" frames="$2" out="$3"
    "$bin" --headless --preset "$preset" --frames "$frames" --size 960x540 --out "$tmp/$preset" > /dev/null
    cp "$tmp/$preset/$(printf 'frame_%05d.png' $((frames - 1)))" "$out"
}
frame sphere-two-orbits 60 docs/render/sphere-two-orbits.png
frame cylinder-near-critical 60 docs/render/cylinder-near-critical.png

# The app's window (1600×900 on a screen larger than that); under Xvfb where there is no display.
window() {
    if [ -n "${DISPLAY:-}" ]; then "$@"; else xvfb-run -a -s "-screen 0 1920x1080x24" "$@"; fi
}
window "$bin" app --preset sphere-two-orbits --screenshot-after 6 docs/render/app.png --exit-after 7
window "$bin" app --preset lesson-critical-angle --screenshot-after 40 docs/lessons/critical-angle.png --exit-after 41
window "$bin" app --preset lesson-inertia-hysteresis --screenshot-after 40 docs/lessons/inertia-hysteresis.png --exit-after 41
window "$bin" app --preset lesson-period-doubling --screenshot-after 85 docs/lessons/period-doubling.png --exit-after 86

# Each lesson on a projector (presentation mode, docs/guide/lessons.md) at its key step, at
# 1280×720 and 1920×1080, and class mode at 1280×720: a virtual screen of that size, the window
# full screen, opened at the step (--step) with the step's evidence on its plot.
screen() {
    local size="$1"
    shift
    xvfb-run -a -s "-screen 0 ${size}x24" "$@"
}
for lesson_step in critical-angle:7 inertia-hysteresis:8 period-doubling:3; do
    lesson="${lesson_step%:*}"
    step="${lesson_step#*:}"
    for size in 1280x720 1920x1080; do
        screen "$size" "$bin" app --preset "lesson-$lesson" --present --step "$step" \
            --screenshot-after 6 "docs/presentation/lesson-$lesson-$size.png" --exit-after 7
    done
done
screen 1280x720 "$bin" app --preset lesson-period-doubling --class --step 3 --screenshot-after 6 \
    docs/presentation/class-mode-1280x720.png --exit-after 7

# Several bodies on one ramp (docs/guide/scenes.md, app.md): "which one stops?" at its end, and
# the period-doubling lesson's side-by-side step on a 1920×1080 projector and as a headless frame.
mkdir -p docs/bodies
"$bin" --headless --preset which-one-stops --frames all --out "$tmp/which" > /dev/null
cp "$tmp/which/$(ls "$tmp/which" | sort | tail -1)" docs/bodies/which-one-stops-end.png
screen 1920x1080 "$bin" app --preset lesson-period-doubling --present --step 5 --screenshot-after 8 \
    docs/bodies/doubling-side-by-side-present-1920x1080.png --exit-after 9
"$bin" scenes --toml lesson-period-doubling | sed 's/^trail_time = 120.0/&\nstart_time = 4200.0/' \
    > "$tmp/side-by-side.toml"
"$bin" --headless --scene "$tmp/side-by-side.toml" --frames 1 --size 1920x1080 --out "$tmp/side" > /dev/null
cp "$tmp/side/frame_00000.png" docs/bodies/doubling-side-by-side-1920x1080.png

# Sculpting (docs/guide/app.md): the paper's body before and after one pulled bump, from the
# test that checks α* and the drift change with it.
ROLLPHASE_SCREENSHOTS="$PWD/docs/sculpt" cargo test -q --test app -- --ignored --exact \
    sculpt::a_strokes_before_and_after_show_alpha_star_and_the_drift_change

# The app's measuring sweeps (docs/guide/app.md): α up across α* on a cylinder from 0.96 α*,
# α down across α* on a sphere, m/m0 up across the flip; each window's screenshot as it ends
# and its plot data (--plot-data writes them as the window closes).
cat > "$tmp/cylinder-below.toml" <<TOML
name = "cylinder-below-critical"
description = "The cylinder of cylinder-near-critical at 0.96 α*, for a sweep up across α*"
[body]
shape = "$PWD/assets/shapes/disk.json"
[model]
alpha_over_critical = 0.96
mass_ratio = 0.0
TOML
app_sweep() {
    local name="$1" seconds="$2"
    shift 2
    window "$bin" app "$@" --speed 1000 --screenshot-after "$seconds" "docs/app-sweeps/$name.png" \
        --exit-after "$((seconds + 1))" --plot-data "$tmp/app-sweep-$name"
    cp "$tmp/app-sweep-$name"/sweep-*.csv "$tmp/app-sweep-$name/plot-data.json" \
        "docs/app-sweeps/$name/"
}
app_sweep cylinder-alpha 60 --scene "$tmp/cylinder-below.toml" --sweep alpha:0.0005:0.065
app_sweep sphere-alpha 80 --preset sphere-cruising --sweep alpha:-0.01:0.1
app_sweep sphere-mass 80 --preset sphere-flip --sweep mass:0.05:10

# The plots' data of one α sweep and one m/m0 sweep (the two lessons that sweep them).
# Only the sweeps are kept: the time series run to 40,000 rows (a sample every 0.1 t).
for lesson in critical-angle period-doubling; do
    "$bin" --headless --preset "lesson-$lesson" --frames all --size 160x90 --msaa 1 \
        --out "$tmp/plot-frames-$lesson" --plot-data "$tmp/plot-data-$lesson" > /dev/null
    cp "$tmp/plot-data-$lesson"/sweep-*.csv "docs/plot-data/lesson-$lesson/"
done

# From experiment to model (docs/guide/experiments.md): the printed sphere fitted, its orbits'
# paths at sin α = 0.2, and the authors' tracked run against them.
"$bin" shape --from-mesh assets/data/printed-sphere.stl -o "$tmp/printed-sphere.json" 2> /dev/null
"$bin" predict "$tmp/printed-sphere.json" --alpha 0.2014 --figure docs/experiments/predicted-paths.png > /dev/null
"$bin" track assets/data/sphere-track-viscous.csv --markers assets/data/sphere-markers-viscous.csv \
    --body "$tmp/printed-sphere.json" --alpha 0.2014 --out "$tmp/run" > /dev/null 2>&1
cp "$tmp/run/figure.png" docs/experiments/tracked-run.png

# Design a body (docs/guide/design.md): the designed sphere's orbit diagram in m/m0 beside the
# printed sphere's, at sin α = 0.2.
"$bin" figure sphere-bifurcation --shape docs/design/doubling-sphere.json --alpha 0.2014 \
    --out "$tmp/designed" > /dev/null
cp "$tmp/designed/sphere-bifurcation/figure.png" docs/design/bifurcation-designed.png
"$bin" figure sphere-bifurcation --shape "$tmp/printed-sphere.json" --alpha 0.2014 \
    --out "$tmp/printed" > /dev/null
cp "$tmp/printed/sphere-bifurcation/figure.png" docs/design/bifurcation-printed.png

"$bin" bench accuracy --out docs/accuracy
"$bin" bench stiff --out docs/stiff

# The Python module's figures (docs/python/fig3d.png, fig4e.png), from a fresh virtual
# environment with the module built from this checkout.
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install -q ./python matplotlib
"$tmp/venv/bin/python" docs/python/paper_figures.py docs/python
