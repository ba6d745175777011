//! The rendering command line as a user meets it: `--headless` writes numbered PNG frames of
//! the asked size; `scenes` lists every preset; `export-stl` writes a watertight mesh of the
//! right size; bad input exits non-zero with one line naming the value and what is allowed.
#![cfg(feature = "render")]

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::{Command, Output};

fn rollphase(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(args)
        .output()
        .unwrap()
}

fn temp(name: &str) -> PathBuf {
    let dir = crate::cli::scratch(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn headless_writes_numbered_frames_of_the_asked_size() {
    let dir = temp("headless");
    let out = dir.join("frames");
    let o = rollphase(&[
        "--headless",
        "--frames",
        "3",
        "--size",
        "200x120",
        "--preset",
        "cylinder-hysteresis",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        let img = image::open(out.join(format!("frame_{k:05}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (200, 120));
    }
    assert!(!out.join("frame_00003.png").exists());
}

#[test]
fn headless_reads_a_scene_file() {
    let dir = temp("scene-file");
    let scene = dir.join("s.toml");
    std::fs::write(
        &scene,
        "name = \"mine\"\n[body]\nrandom = { dimension = 3, seed = 1, sigma = 0.25 }\n[model]\nalpha_rad = 0.4\n",
    )
    .unwrap();
    let out = dir.join("f");
    let o = rollphase(&[
        "--headless",
        "--scene",
        scene.to_str().unwrap(),
        "--size",
        "64x64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("frame_00000.png").exists());
}

#[test]
fn frames_all_renders_a_lesson_up_to_its_end_through_its_speed_steps() {
    let dir = temp("lesson");
    let scene = dir.join("lesson.toml");
    // 1 s of video at speed 6, then 0.5 s at speed 60 up to end_time = 36: 46 frames at 30 fps.
    std::fs::write(
        &scene,
        "name = \"short\"\n[body]\nperfect = \"disk\"\n[model]\nalpha_rad = 0.3\n\
         [playback]\nspeed = 6.0\nend_time = 36.0\n\
         [[timeline]]\nat = 6.0\nspeed = 60.0\ncaption = \"faster\"\n",
    )
    .unwrap();
    let out = dir.join("f");
    let o = rollphase(&[
        "--headless",
        "--scene",
        scene.to_str().unwrap(),
        "--frames",
        "all",
        "--size",
        "64x64",
        "--msaa",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("wrote 46 frame(s)"), "{said}");
    assert!(said.contains("t = 0.000 … 36.000"), "{said}");
    assert!(out.join("frame_00045.png").exists());
    assert!(!out.join("frame_00046.png").exists());
    // Resumed after its end (a saved state at t = 40), `all` has nothing to render: refused, not
    // one frame past the end with exit 0 (a helper's).
    let late = dir.join("late.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(
        &late,
        format!("{text}[resume]\nt = 40.0\nstate = [0.0, 0.0]\n"),
    )
    .unwrap();
    let o = rollphase(&[
        "--headless",
        "--scene",
        late.to_str().unwrap(),
        "--frames",
        "all",
        "--size",
        "64x64",
        "--out",
        dir.join("g").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("t = 36, but it starts after it, at t = 40"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bad_render_input_is_refused_with_the_reason() {
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["--headless", "--size", "12x9000"],
            &["12x9000", "16 ≤ width"],
        ),
        (&["--headless", "--size", "big"], &["WIDTHxHEIGHT"]),
        (
            &["--headless", "--preset", "nope"],
            &["no preset named \"nope\"", "sphere-cruising"],
        ),
        (&["--headless", "--frames", "0"], &["--frames 0"]),
        (
            &["--headless", "--frames", "abc"],
            &["--frames \"abc\"", "`all`"],
        ),
        (
            &["--headless", "--frames", "all"],
            &["sphere-cruising sets none", "playback.end_time"],
        ),
        (
            &["--headless", "--scene", "/nonexistent/s.toml"],
            &["/nonexistent/s.toml"],
        ),
    ];
    for (args, needles) in cases {
        let o = rollphase(args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let e = stderr(&o);
        for n in *needles {
            assert!(e.contains(n), "{args:?}: {e:?} lacks {n:?}");
        }
    }
}

#[test]
fn no_adapter_is_one_line_saying_what_to_install() {
    // Metal exists on no machine this runs on: the same path as a Linux box without Mesa.
    let o = Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(["--headless", "--size", "64x64", "--out"])
        .arg(temp("no-adapter"))
        .env("WGPU_BACKEND", "metal")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.contains("no GPU adapter found") && e.contains("Mesa"),
        "{e}"
    );
    assert_eq!(e.trim().lines().count(), 1, "{e}");
}

#[test]
fn scenes_lists_every_preset_with_its_description() {
    let o = rollphase(&["scenes"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for (name, _) in rollphase::scene::PRESETS {
        let line = text
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("{name} missing"));
        assert!(line.len() > name.len() + 20, "{name} has no description");
    }
    let o = rollphase(&["scenes", "--toml", "perfect-sphere"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("perfect = \"sphere\""));
}

/// Triangles of a binary STL as vertex triples.
fn read_stl(path: &PathBuf) -> Vec<[[f32; 3]; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * n);
    let f = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    (0..n)
        .map(|t| {
            let base = 84 + 50 * t + 12;
            [0, 1, 2].map(|v| [0, 1, 2].map(|c| f(base + 12 * v + 4 * c)))
        })
        .collect()
}

/// Every edge used once in each direction: a closed, consistently oriented surface.
fn watertight(tris: &[[[f32; 3]; 3]]) -> bool {
    let key = |p: [f32; 3]| p.map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    for t in tris {
        for k in 0..3 {
            *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
        }
    }
    edges
        .iter()
        .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
}

fn volume(tris: &[[[f32; 3]; 3]]) -> f64 {
    tris.iter()
        .map(|t| {
            let v = t.map(|p| p.map(|x| x as f64));
            let cross = [
                v[1][1] * v[2][2] - v[1][2] * v[2][1],
                v[1][2] * v[2][0] - v[1][0] * v[2][2],
                v[1][0] * v[2][1] - v[1][1] * v[2][0],
            ];
            (v[0][0] * cross[0] + v[0][1] * cross[1] + v[0][2] * cross[2]) / 6.0
        })
        .sum()
}

#[test]
fn export_stl_writes_a_watertight_body_in_millimetres() {
    let dir = temp("stl");
    let shapes = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes");
    let sphere = dir.join("sphere.stl");
    let o = rollphase(&[
        "export-stl",
        &format!("{shapes}/sphere.json"),
        "-o",
        sphere.to_str().unwrap(),
        "--radius-mm",
        "30",
        "--detail",
        "4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let tris = read_stl(&sphere);
    assert_eq!(tris.len(), 20 * 4usize.pow(4));
    assert!(watertight(&tris));
    // ⟨r⟩ = 1 ↦ 30 mm: the volume is close to a 30 mm ball's (the body's r varies by ±15%).
    let ball = 4.0 / 3.0 * std::f64::consts::PI * 30f64.powi(3);
    let v = volume(&tris);
    assert!(
        v > 0.85 * ball && v < 1.15 * ball,
        "volume {v} mm³ vs ball {ball}"
    );

    let cylinder = dir.join("disk.stl");
    let o = rollphase(&[
        "export-stl",
        &format!("{shapes}/disk.json"),
        "-o",
        cylinder.to_str().unwrap(),
        "--radius-mm",
        "20",
        "--length-mm",
        "10",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let tris = read_stl(&cylinder);
    assert!(watertight(&tris));
    let ys: Vec<f32> = tris.iter().flat_map(|t| t.iter().map(|p| p[1])).collect();
    let (lo, hi) = ys
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &y| (a.min(y), b.max(y)));
    assert!((hi - lo - 10.0).abs() < 1e-4, "length {}", hi - lo);
    let area = std::f64::consts::PI * 400.0;
    assert!((volume(&tris) / (10.0 * area) - 1.0).abs() < 0.05);

    let o = rollphase(&[
        "export-stl",
        &format!("{shapes}/disk.json"),
        "-o",
        "x.stl",
        "--radius-mm",
        "-3",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--radius-mm -3"));
}

#[test]
fn headless_gif_has_every_frame_at_the_asked_size_and_the_scenes_rate() {
    use image::AnimationDecoder;
    let dir = temp("gif");
    let gif = dir.join("clip.gif");
    let o = rollphase(&[
        "--headless",
        "--frames",
        "7",
        "--size",
        "160x90",
        "--preset",
        "cylinder-hysteresis",
        "--gif",
        gif.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let file = std::io::BufReader::new(std::fs::File::open(&gif).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 7);
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (160, 90));
    }
    // The preset plays at 30 frames/s: 7 frames last 23 centiseconds in all.
    let total_ms: u32 = frames
        .iter()
        .map(|f| {
            let (n, d) = f.delay().numer_denom_ms();
            n / d
        })
        .sum();
    assert_eq!(total_ms, 230);
    // Not a blank clip: the body and the ramp are drawn.
    let first = frames[0].buffer();
    let distinct: std::collections::HashSet<_> = first.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 20, "{} colours", distinct.len());
    // No PNG frames and no partial file left beside it.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["clip.gif"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mp4_without_ffmpeg_and_gif_without_headless_say_what_to_do() {
    let dir = temp("clip-refusals");
    let o = rollphase(&["--gif", dir.join("a.gif").to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--headless"), "{}", stderr(&o));
    let o = rollphase(&[
        "--headless",
        "--gif",
        dir.to_str().unwrap(),
        "--size",
        "64x64",
    ]);
    assert!(stderr(&o).contains("is a folder"), "{}", stderr(&o));
    let has_ffmpeg = Command::new("ffmpeg").arg("-version").output().is_ok();
    if !has_ffmpeg {
        let o = rollphase(&[
            "--headless",
            "--frames",
            "2",
            "--size",
            "64x64",
            "--mp4",
            dir.join("a.mp4").to_str().unwrap(),
        ]);
        assert!(!o.status.success());
        assert!(
            stderr(&o).contains("needs ffmpeg on PATH"),
            "{}",
            stderr(&o)
        );
        assert!(!dir.join("a.mp4").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two 64×64 headless frames with `extra` arguments (the hostile-output tests).
fn two_small_frames(extra: &[&str]) -> Output {
    let mut args = vec!["--headless", "--frames", "2", "--size", "64x64"];
    args.extend_from_slice(extra);
    rollphase(&args)
}

/// A scene file of the default cylinder, for the tests that make it an output too.
fn small_scene(dir: &std::path::Path) -> PathBuf {
    let scene = dir.join("s.toml");
    std::fs::write(
        &scene,
        "name = \"mine\"\n[body]\nrandom = { dimension = 2, seed = 1, sigma = 0.08 }\n[model]\nalpha_rad = 0.4\n",
    )
    .unwrap();
    scene
}

#[test]
fn a_clip_or_frame_that_is_the_scene_is_refused_before_rendering() {
    let dir = temp("clip-is-input");
    let scene = small_scene(&dir);
    let before = std::fs::read(&scene).unwrap();
    let s = scene.to_str().unwrap();
    for flag in ["--gif", "--mp4"] {
        let o = two_small_frames(&["--scene", s, flag, s]);
        assert_eq!(o.status.code(), Some(1), "{flag}: {}", stderr(&o));
        assert!(stderr(&o).contains("is also an input"), "{}", stderr(&o));
    }
    // A PNG frame whose name links to the scene.
    let frames = dir.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    std::os::unix::fs::symlink(&scene, frames.join("frame_00000.png")).unwrap();
    let o = two_small_frames(&["--scene", s, "--out", frames.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("is also an input"), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&scene).unwrap(),
        before,
        "the scene is untouched"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_clip_to_a_device_is_written_through_and_hard_links_share_it() {
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    let dir = temp("clip-device");
    // A private null device (major 1, minor 3), so a regression replaces it and not /dev/null.
    let null = dir.join("null");
    let made = Command::new("mknod")
        .arg(&null)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    if made {
        let o = two_small_frames(&["--gif", null.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let m = std::fs::metadata(&null).unwrap();
        assert!(m.file_type().is_char_device(), "still a device");
    }
    // h2 is a hard link to h1: after --gif h1 both names hold the new clip.
    let h1 = dir.join("h1.gif");
    std::fs::write(&h1, "old").unwrap();
    std::fs::hard_link(&h1, dir.join("h2.gif")).unwrap();
    let o = two_small_frames(&["--gif", h1.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let h2 = dir.join("h2.gif");
    assert_eq!(std::fs::read(&h1).unwrap(), std::fs::read(&h2).unwrap());
    assert!(std::fs::read(&h2).unwrap().starts_with(b"GIF8"));
    assert_eq!(
        std::fs::metadata(&h1).unwrap().ino(),
        std::fs::metadata(&h2).unwrap().ino()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_clip_in_a_missing_folder_says_so_once() {
    let dir = temp("clip-nodir");
    let o = two_small_frames(&["--gif", dir.join("nodir/x.gif").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");
    assert!(err.contains("nodir"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--plot-data DIR` writes the app's plot data of a headless run as CSV files and their metadata (a lesson
/// that sweeps m/m0 gives the mass sweep); a file, a non-folder or a missing --headless is
/// refused before any frame is rendered, and nothing is left behind.
#[test]
fn plot_data_writes_the_plots_csv_of_a_headless_run() {
    let dir = temp("plot-data");
    let data = dir.join("data");
    let o = two_small_frames(&[
        "--preset",
        "sphere-cruising",
        "--out",
        dir.join("frames").to_str().unwrap(),
        "--plot-data",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |name: &str| std::fs::read_to_string(data.join(name)).unwrap();
    assert!(
        read("sweep-alpha.csv").starts_with("direction,alpha,inverse_period,mass_ratio,drag\n")
    );
    assert!(read("series.csv").starts_with("t,contact_theta,contact_phi,angular_speed\n"));
    assert!(read("plot-data.json").contains("\"scene\": \"sphere-cruising\""));
    assert!(read("sweep-mass.csv").starts_with("mass_ratio,polar_angle,drag\n"));
    let health = read("health.csv");
    assert!(
        health.starts_with("t,quat_norm_error,contact_normal_error\n"),
        "a viscous sphere: no energy column\n{health}"
    );
    // One row every PLOT_SAMPLE_DT of simulation time from t = 0, however many frames.
    let times = |csv: &str| -> Vec<f64> {
        csv.lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let t = times(&health);
    assert!(t.len() >= 3, "{health}");
    for (k, t) in t.iter().enumerate() {
        assert_eq!(*t, k as f64 * rollphase::live::PLOT_SAMPLE_DT, "{health}");
    }
    let forces = read("contact-force.csv");
    assert!(
        forces.starts_with("t,normal_force,friction_needed\n"),
        "{forces}"
    );
    assert_eq!(times(&forces), t, "{forces}");
    // Refusals: the destination is a file; no --headless.
    let file = dir.join("a-file");
    std::fs::write(&file, "keep").unwrap();
    let o = two_small_frames(&[
        "--out",
        dir.join("frames2").to_str().unwrap(),
        "--plot-data",
        file.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--plot-data"), "{}", stderr(&o));
    assert!(!dir.join("frames2").exists(), "refused before rendering");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep");
    // Without --headless it is the window's (written as the window closes): with no display
    // there is no window, and nothing is written.
    let o = Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(["--plot-data", data.to_str().unwrap()])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no display"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 33, case 10: an ffmpeg that writes more than a pipe holds (64 KiB) to standard error
/// while reading frames no longer deadlocks the MP4 writer. A stand-in `ffmpeg` on PATH writes
/// 256 KiB of warnings before it reads a byte, then the frames, then the file it was given.
#[test]
fn an_ffmpeg_that_floods_standard_error_does_not_stall_the_clip() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp("ffmpeg-flood");
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let fake = bin.join("ffmpeg");
    std::fs::write(
        &fake,
        "#!/bin/sh\n\
         [ \"$1\" = -version ] && { echo fake; exit 0; }\n\
         for last; do :; done\n\
         head -c 262144 /dev/zero | tr '\\0' w >&2\n\
         cat > /dev/null\n\
         printf 'mp4 from the stand-in' > \"$last\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let clip = dir.join("a.mp4");
    let mut child = Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(["--headless", "--frames", "3", "--size", "256x256", "--mp4"])
        .arg(&clip)
        .env("PATH", path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if started.elapsed().as_secs() > 60 {
            let _ = child.kill();
            panic!("the MP4 writer stalled on ffmpeg's standard error");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(status.success(), "{err}");
    assert_eq!(
        std::fs::read_to_string(&clip).unwrap(),
        "mp4 from the stand-in"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 33, case 10: `bench render` bounds its frame count before any work.
#[test]
fn bench_render_refuses_a_frame_count_beyond_its_bound() {
    let o = rollphase(&["bench", "render", "--frames", "100000000000"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("1 ≤ frames ≤ 100000"), "{}", stderr(&o));
}

/// Issue 33, case 9: headless frames are committed as a set. A frame that cannot be written
/// (here frame 5 is a folder; a full disk does the same) leaves every old frame as it was, says
/// which file and why, and leaves no staged file behind.
#[test]
fn headless_frames_are_committed_as_a_set() {
    let dir = temp("frames-as-a-set");
    for k in 0..8 {
        std::fs::write(dir.join(format!("frame_{k:05}.png")), format!("old {k}")).unwrap();
    }
    std::fs::remove_file(dir.join("frame_00005.png")).unwrap();
    std::fs::create_dir(dir.join("frame_00005.png")).unwrap();
    let o = rollphase(&[
        "--headless",
        "--frames",
        "8",
        "--size",
        "64x64",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("frame_00005.png") && stderr(&o).contains("is a folder"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("see the error that follows"));
    for k in [0, 1, 2, 3, 4, 6, 7] {
        assert_eq!(
            std::fs::read_to_string(dir.join(format!("frame_{k:05}.png"))).unwrap(),
            format!("old {k}"),
            "frame {k} was replaced though the set failed"
        );
    }
    let hidden: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(hidden.is_empty(), "left behind: {hidden:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 33, case 11: a scene named like one of the frames in --out is refused before the
/// frames are rendered (it was refused when its frame's turn came, after the work).
#[test]
fn a_scene_named_like_a_frame_in_out_is_refused_before_rendering() {
    let dir = temp("scene-like-frame");
    let scene = dir.join("frame_00001.png");
    std::fs::write(
        &scene,
        "name = \"mine\"\n[body]\nrandom = { dimension = 2, seed = 1, sigma = 0.08 }\n[model]\nalpha_rad = 0.4\n",
    )
    .unwrap();
    let before = std::fs::read(&scene).unwrap();
    let o = two_small_frames(&[
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("named like frame 1"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    assert!(
        !dir.join("frame_00000.png").exists(),
        "no frame was written"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Where only CPU renderers exist, the render goes through llvmpipe's GL, the faster of Mesa's
/// two (lavapipe's Vulkan is not even loaded), says so, and prints no `error:` line: loading
/// lavapipe without a session made libwayland print "error: XDG_RUNTIME_DIR is invalid or not
/// set" twice on every successful render. `.ci/run` installs lavapipe so this is tested with it.
#[test]
fn a_render_on_a_cpu_renderer_takes_gl_and_prints_no_error_line() {
    let dir = temp("quiet");
    let o = Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WGPU_BACKEND")
        .args([
            "--headless",
            "--frames",
            "2",
            "--size",
            "160x90",
            "--out",
            dir.join("f").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        !err.lines().any(|l| l.trim_start().starts_with("error")),
        "{err}"
    );
    let said = String::from_utf8_lossy(&o.stdout);
    if said.contains("Cpu)") {
        assert!(said.contains("(Gl, Cpu)"), "{said}");
    }
}
