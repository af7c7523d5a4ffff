//! `topoccd render` end to end: the built binary on small OBJ meshes written to a temporary
//! folder, the PNG decoded and checked; bad input refused with a message naming the problem.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const WHITE: [u8; 3] = [255, 255, 255];

/// A fresh folder under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("topoccd-render-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the temporary folder");
        Self(dir)
    }

    fn path(&self, file: &str) -> PathBuf {
        self.0.join(file)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Two separate tetrahedra (eight triangles), the second shifted by `dx` along x.
fn two_tetrahedra(dx: f64) -> String {
    let mut s = String::from("# two tetrahedra\n");
    for shift in [0.0, 2.0 + dx] {
        for [x, y, z] in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ] {
            s += &format!("v {} {y} {z}\n", x + shift);
        }
    }
    for base in [0, 4] {
        for [a, b, c] in [[1, 3, 2], [1, 2, 4], [1, 4, 3], [2, 3, 4]] {
            s += &format!("f {} {} {}\n", a + base, b + base, c + base);
        }
    }
    s
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).expect("write a test input");
}

fn topoccd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .output()
        .expect("run topoccd")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn s(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 temporary path")
}

fn decode(path: &Path) -> image::RgbImage {
    image::open(path).expect("a PNG").to_rgb8()
}

fn count(img: &image::RgbImage, keep: impl Fn([u8; 3]) -> bool) -> usize {
    img.pixels().filter(|p| keep(p.0)).count()
}

#[test]
fn draws_each_colouring_at_the_requested_size() {
    let dir = TempDir::new("modes");
    let mesh = dir.path("mesh.obj");
    write(&mesh, &two_tetrahedra(0.0));
    for (color, expect) in [
        ("clusters", "clusters: "),
        (
            "objects",
            "objects: 2 connected components over 8 triangles",
        ),
    ] {
        let png = dir.path(&format!("{color}.png"));
        let out = topoccd(&[
            "render",
            s(&mesh),
            "--color",
            color,
            "--size",
            "120x80",
            "--out",
            s(&png),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(stderr(&out).contains(expect), "{}", stderr(&out));
        let img = decode(&png);
        assert_eq!(img.dimensions(), (120, 80));
        let drawn = count(&img, |p| p != WHITE);
        assert!(drawn > 120 * 80 / 8, "{color}: {drawn} pixels drawn");
        // Framed: the border rows and columns stay background.
        for x in 0..120 {
            assert_eq!(img.get_pixel(x, 0).0, WHITE);
            assert_eq!(img.get_pixel(x, 79).0, WHITE);
        }
    }
}

#[test]
fn default_size_and_deterministic_bytes_and_indexed_output() {
    let dir = TempDir::new("default");
    let mesh = dir.path("mesh.obj");
    write(&mesh, &two_tetrahedra(0.0));
    let (a, b, c) = (dir.path("a.png"), dir.path("b.png"), dir.path("c.png"));
    for png in [&a, &b] {
        let out = topoccd(&["render", s(&mesh), "--out", s(png)]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    assert_eq!(decode(&a).dimensions(), (1024, 768));
    let bytes = std::fs::read(&a).expect("read the PNG");
    assert_eq!(bytes, std::fs::read(&b).expect("read the PNG"));
    // Overwriting an existing PNG is fine; --indexed stores a palette.
    let out = topoccd(&["render", s(&mesh), "--indexed", "--out", s(&c)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = topoccd(&["render", s(&mesh), "--indexed", "--out", s(&c)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(decode(&c).dimensions(), (1024, 768));
    assert!(std::fs::metadata(&c).expect("the PNG").len() < bytes.len() as u64);
}

#[test]
fn contacts_are_computed_without_a_pairs_file() {
    // The second tetrahedron moves through the first during the step: the query finds contacts.
    let dir = TempDir::new("computed");
    let (t0, t1, png) = (
        dir.path("t0.obj"),
        dir.path("t1.obj"),
        dir.path("computed.png"),
    );
    write(&t0, &two_tetrahedra(1.0));
    write(&t1, &two_tetrahedra(-2.8));
    let out = topoccd(&[
        "render",
        s(&t0),
        "--step",
        s(&t1),
        "--color",
        "contacts",
        "--out",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("contacts in the step"),
        "{}",
        stderr(&out)
    );
    assert!(!stderr(&out).contains(" 0 vf and 0 ee"), "{}", stderr(&out));
    assert!(
        decode(&png).pixels().any(|p| p[0] > 150 && p[1] < 90),
        "no red pixel"
    );
}

#[test]
fn a_step_with_contacts_from_a_pairs_file() {
    let dir = TempDir::new("contacts");
    let (t0, t1) = (dir.path("t0.obj"), dir.path("t1.obj"));
    write(&t0, &two_tetrahedra(0.0));
    write(&t1, &two_tetrahedra(-1.5));
    let pairs = dir.path("pairs.csv");
    // Vertex 4 (the second tetrahedron's corner) hits face 3 of the first.
    write(&pairs, "# kind,...\nvf,4,3,0.5\n");
    let png = dir.path("contacts.png");
    let out = topoccd(&[
        "render",
        s(&t0),
        "--step",
        s(&t1),
        "--color",
        "contacts",
        "--pairs",
        s(&pairs),
        "--camera",
        "-20,-10",
        // y up, as this test was written for: `--up auto` would pick x, as the second
        // tetrahedron moves down x (a fall, for the heuristic) during the step.
        "--up",
        "y",
        "--size",
        "200x150",
        "--out",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("1 vertex-face and 0 edge-edge contacts involve 4 of 8 triangles"),
        "{}",
        stderr(&out)
    );
    let red = |img: &image::RgbImage| count(img, |[r, g, b]| r > 60 && g < 30 && b < 30);
    let img = decode(&png);
    let grey = count(&img, |[r, g, b]| r == g && g > 60 && r < 250 && b < 250);
    assert!(
        red(&img) > 100 && grey > 100,
        "red {}, grey {grey}",
        red(&img)
    );
    // Far apart tetrahedra, contacts on the first only (the edges 0-1 and 2-3): framed on
    // them, the red part grows.
    let far = dir.path("far.obj");
    write(&far, &two_tetrahedra(6.0));
    let pairs = dir.path("first.csv");
    write(&pairs, "ee,0,1,2,3,0.25\n");
    let red_pixels = |fit: &str| {
        let png = dir.path(&format!("fit-{fit}.png"));
        let out = topoccd(&[
            "render",
            s(&far),
            "--color",
            "contacts",
            "--pairs",
            s(&pairs),
            "--size",
            "200x150",
            "--fit",
            fit,
            "--out",
            s(&png),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        red(&decode(&png))
    };
    let (whole, zoomed) = (red_pixels("mesh"), red_pixels("contacts"));
    assert!(
        zoomed > whole * 3 / 2,
        "{zoomed} red pixels zoomed, {whole} unzoomed"
    );
}

#[test]
fn bad_input_fails_with_a_message_naming_the_problem() {
    let dir = TempDir::new("errors");
    let mesh = dir.path("mesh.obj");
    let text = two_tetrahedra(0.0);
    write(&mesh, &text);
    let png = dir.path("out.png");
    let fails = |args: &[&str], needle: &str| {
        let out = topoccd(args);
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = stderr(&out);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    };
    let missing = dir.path("missing.obj");
    fails(&["render", s(&missing), "--out", s(&png)], s(&missing));
    fails(
        &["render", s(&mesh), "--out", s(&mesh)],
        "--out must name a .png file",
    );
    // The same file under another name is still refused, and left alone.
    let png_named_mesh = dir.path("mesh.png");
    write(&png_named_mesh, &text);
    let other_name = format!("{}/./mesh.png", dir.0.display());
    fails(
        &["render", s(&png_named_mesh), "--out", &other_name],
        "names an input file",
    );
    fails(
        &[
            "render",
            s(&mesh),
            "--step",
            s(&png_named_mesh),
            "--out",
            s(&png_named_mesh),
        ],
        "names an input file",
    );
    assert_eq!(
        std::fs::read_to_string(&png_named_mesh).expect("still there"),
        text
    );
    fails(
        &["render", s(&mesh), "--camera", "35", "--out", s(&png)],
        "--camera",
    );
    fails(
        &["render", s(&mesh), "--camera", "0,100", "--out", s(&png)],
        "elevation",
    );
    fails(
        &["render", s(&mesh), "--size", "0x10", "--out", s(&png)],
        "--size",
    );
    let pairs = dir.path("pairs.csv");
    write(&pairs, "vf,0,0,0.5\nvf,0,99,0.5\n");
    fails(
        &[
            "render",
            s(&mesh),
            "--color",
            "contacts",
            "--pairs",
            s(&pairs),
            "--out",
            s(&png),
        ],
        &format!("{}:2: face 99 is out of range", pairs.display()),
    );
    fails(
        &["render", s(&mesh), "--fit", "contacts", "--out", s(&png)],
        "--fit contacts needs --color contacts",
    );
    let broken = dir.path("broken.obj");
    write(&broken, "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    fails(&["render", s(&broken), "--out", s(&png)], s(&broken));
    assert!(!png.exists(), "no picture is written when the input is bad");
}

/// A unit square of two triangles in the plane z = `z`, cut along its diagonal 1-2 in the
/// second frame (vertices 4 and 5 copy 1 and 2, the second triangle uses them): the two sides
/// of the cut touch at t=0 (crack contacts), and the second triangle drops by `drop`.
fn cut_square(dir: &TempDir, drop: f64) -> (PathBuf, PathBuf) {
    let (t0, t1) = (dir.path("0000.obj"), dir.path("0001.obj"));
    write(
        &t0,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    );
    write(
        &t1,
        &format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 {d}\nv 1 0 {d}\nv 0 1 {d}\nf 1 2 3\nf 5 4 6\n",
            d = -drop
        ),
    );
    write(&dir.path("0001.parents"), "4 1\n5 2\n");
    (t0, t1)
}

#[test]
fn pictures_carry_a_title_and_a_legend_above_the_mesh() {
    let dir = TempDir::new("legend");
    let (t0, t1) = cut_square(&dir, 0.3);
    let png = dir.path("legend.png");
    let out = topoccd(&[
        "render",
        s(&t0),
        "--step",
        s(&t1),
        "--color",
        "contacts",
        "--out",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let img = decode(&png);
    // The band above the mesh: dark text (the title, the labels) and the swatches' colours.
    let band = |keep: &dyn Fn([u8; 3]) -> bool| {
        (0..90)
            .flat_map(|y| (0..1024).map(move |x| (x, y)))
            .filter(|&(x, y)| keep(img.get_pixel(x, y).0))
            .count()
    };
    let dark = band(&|[r, g, b]| r < 90 && g < 90 && b < 90);
    assert!(dark > 300, "{dark} dark text pixels in the band");
    let crack_swatch = band(&|p| p == [240, 165, 20]);
    let red_swatch = band(&|p| p == [220, 25, 20]);
    assert!(
        crack_swatch > 50 && red_swatch > 50,
        "{crack_swatch} {red_swatch}"
    );
    // Small pictures are left as the mesh alone: no text over it.
    let small = dir.path("small.png");
    let out = topoccd(&[
        "render",
        s(&t0),
        "--step",
        s(&t1),
        "--size",
        "200x150",
        "--out",
        s(&small),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let img = decode(&small);
    assert_eq!(count(&img, |[r, g, b]| r < 90 && g < 90 && b < 90), 0);
}

#[test]
fn crack_contacts_are_coloured_apart_from_collisions_and_the_end_shows_as_a_ghost() {
    let dir = TempDir::new("crack");
    let (t0, t1) = cut_square(&dir, 0.3);
    let png = dir.path("crack.png");
    let out = topoccd(&[
        "render",
        s(&t0),
        "--step",
        s(&t1),
        "--color",
        "contacts",
        "--size",
        "300x200",
        "--out",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("crack contacts (features joined through a split vertex): "),
        "{err}"
    );
    assert!(!err.contains("split vertex): 0 of"), "{err}");
    let img = decode(&png);
    // Below the band: both triangles touch only along the cut, so they are in the crack colour
    // (orange: red high, green middle, blue low), none in the collision red.
    let mesh = |keep: &dyn Fn([u8; 3]) -> bool| {
        (60..200)
            .flat_map(|y| (0..300).map(move |x| (x, y)))
            .filter(|&(x, y)| keep(img.get_pixel(x, y).0))
            .count()
    };
    let orange = mesh(&|[r, g, b]| r > 120 && g > 50 && g < r && b < g / 2);
    let red = mesh(&|[r, g, b]| r > 60 && g < 30 && b < 30);
    assert!(orange > 500 && red == 0, "orange {orange}, red {red}");
    // The dropped triangle's end position: a blue outline.
    let blue = mesh(&|[r, g, b]| b > 150 && r < 120 && g < 160);
    assert!(blue > 50, "{blue} ghost pixels");
    // Without motion, no ghost.
    let still = dir.path("still.png");
    let out = topoccd(&[
        "render",
        s(&t0),
        "--color",
        "contacts",
        "--size",
        "300x200",
        "--out",
        s(&still),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let img = decode(&still);
    assert_eq!(count(&img, |[r, g, b]| b > 150 && r < 120 && g < 160), 0);
}

#[test]
fn the_up_axis_is_chosen_from_the_data() {
    // A 4 x 1 sheet in the plane z = 0 (thinnest along z): auto picks z, and the sheet, seen
    // from 25 degrees above its plane, is much wider than tall; with y forced, it faces the
    // camera and looks much taller than it does lying down.
    let dir = TempDir::new("up");
    let sheet = dir.path("sheet.obj");
    write(
        &sheet,
        "v 0 0 0\nv 4 0 0\nv 0 1 0\nv 4 1 0\nf 1 2 3\nf 2 4 3\n",
    );
    let height_of_drawing = |up: Option<&str>| {
        let png = dir.path(&format!("up-{}.png", up.unwrap_or("auto")));
        let mut args = vec!["render", s(&sheet), "--size", "300x200", "--out", s(&png)];
        if let Some(up) = up {
            args.extend(["--up", up]);
        }
        let out = topoccd(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        let img = decode(&png);
        let rows: Vec<u32> = (0..200)
            .filter(|&y| (0..300).any(|x| img.get_pixel(x, y).0 != WHITE))
            .collect();
        (stderr(&out), rows.len())
    };
    let (err, auto) = height_of_drawing(None);
    assert!(
        err.contains("up axis: z (the mesh is a sheet, thinnest along z"),
        "{err}"
    );
    let (err, z) = height_of_drawing(Some("z"));
    assert!(err.contains("up axis: z (--up z)"), "{err}");
    let (_, y) = height_of_drawing(Some("y"));
    assert_eq!(auto, z);
    assert!(2 * y > 3 * z, "rows drawn: {y} with y up, {z} with z up");
}
