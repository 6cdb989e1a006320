//! Snapshot tests of scenes: the statistical comparison passes renders that differ only in their
//! noise and fails real changes, at the tiles where they are; `raydiance snapshot` end to end.

use std::path::Path;
use std::process::{Command, Output};

use glam::Vec3;
use raydiance::progress::Silent;
use raydiance::render::render;
use raydiance::snapshot::{self, Comparison, Estimate, FINEST_TILE, Rect, compare};

const SIZE: usize = snapshot::DEFAULT_LONGER_SIDE as usize;

/// The render `raydiance snapshot` makes by default (square scenes: 64x64, 64 spp) of scene
/// text that stands in `scenes/` (so it can include the lab box), with the given seed.
fn estimate(text: &str, seed: u64) -> Estimate {
    let mut graph = raydiance::lang::parse_scene(Path::new("scenes/snapshot-test.scn"), text)
        .unwrap_or_else(|e| panic!("{e}"));
    graph.settings.width = SIZE as u32;
    graph.settings.height = SIZE as u32;
    graph.settings.samples = snapshot::DEFAULT_SAMPLES;
    graph.settings.seed = seed;
    let scene = raydiance::scene::build(&graph).unwrap_or_else(|e| panic!("{e}"));
    Estimate::from_film(&render(&scene, &Silent).0).unwrap()
}

/// S3 (`scenes/cornell-area.scn`) with a light of the given emission, the left sphere's
/// reflectance and its centre.
fn cornell(emission: f32, left_colour: Vec3, left_centre: Vec3) -> String {
    let [r, g, b] = left_colour.to_array();
    let [x, y, z] = left_centre.to_array();
    format!(
        "#include \"lab-box.inc\"
         settings {{ integrator path  max_depth 32 }}
         quad {{ <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5>  material {{ emission rgb {emission} }} }}
         sphere {{ <{x}, {y}, {z}>, 0.3  material {{ diffuse rgb <{r}, {g}, {b}> }} }}
         sphere {{ RightSphere, 0.3  material {{ Yellow }} }}"
    )
}

const LEFT_COLOUR: Vec3 = Vec3::new(0.2, 0.4, 0.8);
const LEFT_CENTRE: Vec3 = Vec3::new(-0.5, -0.7, 0.25);

/// The pixels that a sphere covers under the lab camera (origin (0, 0, -3.5), image plane
/// [-1, 1]² at distance 3, column 0 at x = -1, row 0 at y = +1), widened by one finest tile for
/// its shadow and the light it reflects onto what is next to it.
fn screen_box(centre: Vec3, radius: f32) -> Rect {
    let scale = 3.0 / (centre.z + 3.5);
    let to_pixels = |ndc: f32| (ndc + 1.0) / 2.0 * SIZE as f32;
    let (x, y) = (to_pixels(centre.x * scale), to_pixels(-centre.y * scale));
    let reach = radius * scale / 2.0 * SIZE as f32 + FINEST_TILE as f32;
    let clamp = |v: f32| v.clamp(0.0, SIZE as f32) as usize;
    Rect { x0: clamp(x - reach), x1: clamp(x + reach), y0: clamp(y - reach), y1: clamp(y + reach) }
}

fn failing_tiles(comparison: &Comparison) -> Vec<String> {
    comparison.failing().map(|t| format!("{:?} z {}", t.rect, t.z)).collect()
}

/// The seed is the only change: no tile of four scenes (path tracing with caustics and
/// fireflies included) may fail. At the bound's rate of 1 in 10,000 tiles, a false failure in
/// these 340 comparisons would come about once in 30 runs of a correct comparison.
#[test]
fn a_seed_only_change_passes_on_every_tile() {
    let mut compared = 0;
    for scene in ["cornell-area", "cornell-specular", "lab4-gi-point", "lab4-direct"] {
        let text = std::fs::read_to_string(format!("scenes/{scene}.scn")).unwrap();
        let comparison = compare(&estimate(&text, 0), &estimate(&text, 1)).unwrap();
        assert!(comparison.matches(), "{scene}: {:#?}", failing_tiles(&comparison));
        compared += comparison.tiles.len();
    }
    assert!(compared >= 200, "{compared} tiles compared");
}

#[test]
fn a_light_five_percent_brighter_fails() {
    let reference = estimate(&cornell(10.0, LEFT_COLOUR, LEFT_CENTRE), 0);
    let brighter = estimate(&cornell(10.5, LEFT_COLOUR, LEFT_CENTRE), 1);
    let comparison = compare(&reference, &brighter).unwrap();
    let whole = comparison.tiles.last().unwrap();
    assert_eq!(whole.rect, Rect { x0: 0, x1: SIZE, y0: 0, y1: SIZE }, "the last tile is the image");
    assert!(whole.fails() && whole.z.min_element() > 0.0, "the image is brighter: z {}", whole.z);
    assert!(comparison.failing().all(|t| t.worst_z() > 0.0), "{:#?}", failing_tiles(&comparison));
}

/// A change on one object fails, and every failing tile holds some of the object.
fn assert_fails_within(reference: &Estimate, changed: &Estimate, region: Rect) {
    let comparison = compare(reference, changed).unwrap();
    let failing = failing_tiles(&comparison);
    assert!(!comparison.matches(), "the change is found");
    assert!(
        comparison.failing().all(|t| t.rect.overlaps(&region)),
        "outside {region:?}: {failing:#?}"
    );
    let finest = comparison.failing().filter(|t| t.level == 0).count();
    assert!(finest > 0, "found at the finest tiles, not only over the image: {failing:#?}");
}

#[test]
fn a_colour_change_on_one_object_fails_where_the_object_is() {
    let reference = estimate(&cornell(10.0, LEFT_COLOUR, LEFT_CENTRE), 0);
    let redder = LEFT_COLOUR + Vec3::new(0.1, 0.0, 0.0);
    let changed = estimate(&cornell(10.0, redder, LEFT_CENTRE), 1);
    assert_fails_within(&reference, &changed, screen_box(LEFT_CENTRE, 0.3));
}

/// The view at the sphere's depth is 2 × 3.75 / 3 = 2.5 units wide: 2 % of it is 0.05.
#[test]
fn an_object_moved_by_two_percent_of_the_view_fails_where_it_moved() {
    let reference = estimate(&cornell(10.0, LEFT_COLOUR, LEFT_CENTRE), 0);
    let moved_centre = LEFT_CENTRE + Vec3::new(0.05, 0.0, 0.0);
    let moved = estimate(&cornell(10.0, LEFT_COLOUR, moved_centre), 1);
    let (before, after) = (screen_box(LEFT_CENTRE, 0.3), screen_box(moved_centre, 0.3));
    let region = Rect { x0: before.x0, x1: after.x1, y0: before.y0, y1: after.y1 };
    assert_fails_within(&reference, &moved, region);
}

#[test]
fn snapshot_files_round_trip_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("round.exr");
    let estimate = Estimate {
        width: 3,
        height: 2,
        mean: (0..6)
            .map(|i| Vec3::new(i as f32, 0.5 / (i + 1) as f32, 0.1 + 1e-7 * i as f32))
            .collect(),
        variance: (0..6).map(|i| Vec3::splat(i as f32 * 1e-3)).collect(),
        samples_per_pixel: 64,
    };
    snapshot::write(&path, &estimate).unwrap();
    assert_eq!(snapshot::read(&path).unwrap(), estimate);
}

fn raydiance(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raydiance")).args(args).output().unwrap()
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// A scene of its own (no includes), small and quick: a lit sphere on a floor.
fn small_scene(light: f32) -> String {
    format!(
        "settings {{ resolution 24, 16  integrator path  max_depth 4 }}
         camera {{ location <0, 1, -4>  look_at <0, 0.5, 0>  angle 40 }}
         plane {{ <0, 1, 0>, 0  material {{ diffuse rgb 0.5 }} }}
         sphere {{ <0, 0.5, 0>, 0.5  material {{ diffuse rgb <0.7, 0.3, 0.2> }} }}
         light_source {{ <1, 3, -2>  power rgb {light} }}"
    )
}

#[test]
fn the_command_writes_new_snapshots_accepts_them_and_then_passes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("ball.scn");
    std::fs::write(&scene, small_scene(10.0)).unwrap();
    let folder = dir.path().to_str().unwrap();
    let snapshots = dir.path().join("__snapshots__");

    let first = raydiance(&["snapshot", folder]);
    assert_eq!(first.status.code(), Some(1), "a missing snapshot fails:\n{}", text(&first));
    assert!(text(&first).contains("ball.scn: no snapshot; wrote"), "{}", text(&first));
    assert!(snapshots.join("ball.new.exr").exists() && !snapshots.join("ball.exr").exists());

    let accept = raydiance(&["snapshot", folder, "--accept"]);
    assert!(accept.status.success(), "{}", text(&accept));
    assert!(snapshots.join("ball.exr").exists() && !snapshots.join("ball.new.exr").exists());
    let snapshot = snapshot::read(&snapshots.join("ball.exr")).unwrap();
    assert_eq!((snapshot.width, snapshot.height), (64, 43), "the scene's aspect, 64 wide");

    let again = raydiance(&["snapshot", folder]);
    assert!(again.status.success(), "{}", text(&again));
    assert!(text(&again).contains("1 scenes: 1 match, 0 differ"), "{}", text(&again));

    // Other seeds, threads and sample counts see the same picture.
    let noise =
        raydiance(&["snapshot", scene.to_str().unwrap(), "--samples", "16", "--threads", "1"]);
    assert!(noise.status.success(), "{}", text(&noise));

    std::fs::write(&scene, small_scene(11.0)).unwrap();
    let brighter = raydiance(&["snapshot", folder]);
    assert_eq!(brighter.status.code(), Some(1), "{}", text(&brighter));
    assert!(text(&brighter).contains("ball.scn: differs from its snapshot"), "{}", text(&brighter));
    assert!(text(&brighter).contains("brighter"), "{}", text(&brighter));
    assert!(snapshots.join("ball.new.exr").exists() && snapshots.join("ball.diff.png").exists());
}

#[test]
fn a_corrupt_snapshot_is_an_error_that_names_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ball.scn"), small_scene(10.0)).unwrap();
    let snapshots = dir.path().join("__snapshots__");
    std::fs::create_dir(&snapshots).unwrap();
    std::fs::write(snapshots.join("ball.exr"), b"v/1\x01 not an image").unwrap();
    let output = raydiance(&["snapshot", dir.path().to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let message = text(&output);
    assert!(
        message.contains("__snapshots__/ball.exr: not a readable raydiance snapshot"),
        "{message}"
    );
    assert!(!snapshots.join("ball.new.exr").exists(), "nothing rendered against a bad snapshot");
}

/// A scene whose integrator shares photons among all samples has no per-pixel variance to test:
/// `snapshot` says so and passes it, writing nothing, so `raydiance snapshot scenes/` can pass.
#[test]
fn photon_scenes_are_reported_as_not_snapshotted() {
    let scene = Path::new("scenes/caustic-point.scn");
    let outcome = raydiance::snapshot::check(scene, &Default::default()).unwrap();
    assert_eq!(outcome.verdict, raydiance::snapshot::Verdict::Unsupported { integrator: "sppm" });
    assert!(outcome.summary().contains("not snapshotted"), "{}", outcome.summary());
    assert!(!Path::new("scenes/__snapshots__/caustic-point.new.exr").exists());
}
