//! Helpers shared by the tests: scene edits and scenes several files run, `history.csv`
//! columns, VTU arrays by name, PNG pixels (decoded by the minimal inflate below; `image`
//! is not a dependency of this crate), the field an error names.
#![allow(dead_code)]
use std::collections::HashSet;
use std::path::{Path, PathBuf};

use talus::output::OutputError;

/// Sends `kill -SIGNAL` (e.g. `INT`, `TERM`, `KILL`) to `child` and waits for its output.
pub fn signal(child: std::process::Child, signal: &str) -> std::process::Output {
    let status = std::process::Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(status.success());
    child.wait_with_output().unwrap()
}

/// The 1-based line of `text` holding `needle`.
pub fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

/// `talus run` of the scene `text`, written to `target/tmp/<test>/<name>/scene.toml`, its
/// outputs in `…/out`, logging at `warn`; panics (with its stderr) unless it succeeded.
/// Returns the output folder, stdout and stderr.
pub fn talus_run(test: &str, name: &str, text: &str) -> (PathBuf, String, String) {
    let dir = target_tmp_dir(test, name);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{test}/{name}: {stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    (dir.join("out"), stdout, stderr)
}

/// `target/tmp/<test>/<name>`, created.
pub fn target_tmp_dir(test: &str, name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(test).join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---------------------------------------------------------------- scene text

/// `scenes/footing.toml`.
pub const FOOTING: &str = include_str!("../../../../scenes/footing.toml");

/// `text` with the first `from` replaced by `to`; `from` must be there (a scene edited
/// since would otherwise leave the test running the unedited scene).
pub fn replaced(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "test setup: `{from}` not in the scene");
    text.replacen(from, to, 1)
}

/// `text` with the line `key` added after its first line starting `cone_fit =` (a
/// plane-strain fit, an explicit cone, …): a key of that material (`relaxation_time`,
/// `flow`, …).
pub fn with_material_key(text: &str, key: &str) -> String {
    let start = text
        .lines()
        .scan(0, |at, line| {
            let here = *at;
            *at += line.len() + 1;
            Some((here, line))
        })
        .find(|(_, line)| line.starts_with("cone_fit ="))
        .map(|(at, _)| at)
        .expect("test setup: a `cone_fit =` line in the scene");
    let end = text[start..].find('\n').map_or(text.len(), |n| start + n);
    format!("{}\n{key}{}", &text[..end], &text[end..])
}

/// The FEM scene `text`, parsed (a parse error panics with its message).
pub fn fem(text: &str) -> talus::scene::Scene {
    talus::scene::Scene::parse(text, None).unwrap_or_else(|e| panic!("{e}"))
}

/// Why a model cannot be built from the FEM scene `text` (it must be refused).
pub fn fem_error(text: &str) -> talus::scene::SceneError {
    use talus::model::fem::FromScene;
    talus::model::fem::Model::from_scene(&fem(text))
        .err()
        .expect("the scene must be refused")
}

/// The keys of the footing's `[material]` (without its header).
pub fn footing_soil() -> &'static str {
    let start = FOOTING.find("[material]").unwrap();
    let end = FOOTING[start..].find("\n\n").unwrap() + start;
    &FOOTING[start + "[material]\n".len()..end]
}

/// The footing with its `[material]` made a `[[material]]` list of two layers: "upper"
/// (y > −0.4 m) of the keys `upper`, "lower" of the keys `lower`.
pub fn footing_two_layers(upper: &str, lower: &str) -> String {
    let start = FOOTING.find("[material]").unwrap();
    let end = FOOTING[start..].find("\n\n").unwrap() + start;
    format!(
        "{}[[region]]\nname = \"upper\"\nbox = [[-1.0, -0.4], [1.0, 0.0]]\n\n\
         [[region]]\nname = \"lower\"\nbox = [[-1.0, -1.0], [1.0, -0.4]]\n\n\
         [[material]]\nname = \"upper\"\nregions = [\"upper\"]\n{upper}\n\n\
         [[material]]\nname = \"lower\"\nregions = [\"lower\"]\n{lower}{}",
        &FOOTING[..start],
        &FOOTING[end..]
    )
}

/// A stiff elastic block (0.2 m × 0.2 m, 256 particles, material 0) and a sand column
/// (0.15 m × 0.3 m, 72 particles, material 1) 0.3 m apart on a fixed floor, against a slip
/// left wall; 20 steps, no VTU.
pub const BLOCK_AND_COLUMN: &str = r#"title = "elastic block beside a sand column"
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
spacing = 0.05
cells = [24, 8]

[[body]]
rectangle = [[0.1, 0.0], [0.3, 0.2]]
particles_per_cell = 4
material = "block"

[[body]]
rectangle = [[0.6, 0.0], [0.75, 0.3]]
material = "sand"

[[material]]
name = "block"
model = "elastic"
young_modulus = 1.0e8
poisson_ratio = 0.25
density = 2400.0

[[material]]
name = "sand"
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 0.0
dilatancy_angle = 0.0
cone_fit = "plane_strain"
density = 1800.0

[[wall]]
side = "left"
condition = "slip"

[[wall]]
side = "bottom"
condition = "fixed"

[time]
step = 4.0e-3
steps = 20

[output]
vtu_every = 0
"#;

// ---------------------------------------------------------------- history.csv

/// The column `name` of `out/history.csv`, one value a row from step 0 on (`NaN` as
/// written).
pub fn history_column(out: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {}", out.display()));
    lines
        .map(|l| {
            let cell = l.split(',').nth(col).unwrap();
            cell.parse()
                .unwrap_or_else(|_| panic!("{name}: bad number {cell}"))
        })
        .collect()
}

/// `history.csv` of `out` without its wall-time column.
pub fn history_without_seconds(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("history.csv")).expect("history.csv");
    let header: Vec<&str> = text.lines().next().expect("a header").split(',').collect();
    let seconds = header
        .iter()
        .position(|h| *h == "seconds")
        .expect("a seconds column");
    text.lines()
        .map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells.remove(seconds);
            cells.join(",")
        })
        .collect()
}

// ---------------------------------------------------------------- VTU reading

pub fn attr(xml: &str, name: &str) -> String {
    let key = format!("{name}=\"");
    let start = xml.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len();
    xml[start..start + xml[start..].find('"').unwrap()].to_string()
}

/// The whitespace-separated numbers of the `<DataArray Name="name">`.
pub fn array(xml: &str, name: &str) -> Vec<f64> {
    let key = format!("Name=\"{name}\"");
    let at = xml
        .find(&key)
        .unwrap_or_else(|| panic!("no DataArray {name}"));
    let body = at + xml[at..].find('>').unwrap() + 1;
    let end = body + xml[body..].find("</DataArray>").unwrap();
    xml[body..end]
        .split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .unwrap_or_else(|_| panic!("{name}: bad number {t}"))
        })
        .collect()
}

// ---------------------------------------------------------------- PNG reading

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

pub struct Png {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[u8; 3]>,
}

/// Checks the signature and IHDR, then inflates and unfilters 8-bit RGB or RGBA.
pub fn read_png(path: &Path) -> Png {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(bytes[..8], PNG_SIGNATURE, "{} is not a PNG", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    let (width, height) = (be(&bytes[16..20]), be(&bytes[20..24]));
    let (depth, colour_type, interlace) = (bytes[24], bytes[25], bytes[28]);
    assert_eq!((depth, interlace), (8, 0));
    let channels = match colour_type {
        2 => 3,
        6 => 4,
        t => panic!("unexpected PNG colour type {t}"),
    };
    let mut idat = Vec::new();
    let mut at = 8;
    while at + 8 <= bytes.len() {
        let len = be(&bytes[at..]) as usize;
        if &bytes[at + 4..at + 8] == b"IDAT" {
            idat.extend_from_slice(&bytes[at + 8..at + 8 + len]);
        }
        at += 12 + len;
    }
    let raw = inflate(&idat[2..]); // skip the zlib header
    let stride = width as usize * channels;
    assert_eq!(raw.len(), height as usize * (stride + 1));
    let mut img = vec![0u8; height as usize * stride];
    for y in 0..height as usize {
        let filter = raw[y * (stride + 1)];
        let line = &raw[y * (stride + 1) + 1..(y + 1) * (stride + 1)];
        for x in 0..stride {
            let a = if x >= channels {
                img[y * stride + x - channels]
            } else {
                0
            } as i32;
            let b = if y > 0 { img[(y - 1) * stride + x] } else { 0 } as i32;
            let c = if x >= channels && y > 0 {
                img[(y - 1) * stride + x - channels]
            } else {
                0
            } as i32;
            let predicted = match filter {
                0 => 0,
                1 => a,
                2 => b,
                3 => (a + b) / 2,
                4 => {
                    let p = a + b - c;
                    let (pa, pb, pc) = ((p - a).abs(), (p - b).abs(), (p - c).abs());
                    if pa <= pb && pa <= pc {
                        a
                    } else if pb <= pc {
                        b
                    } else {
                        c
                    }
                }
                f => panic!("bad PNG filter {f}"),
            };
            img[y * stride + x] = (line[x] as i32 + predicted) as u8;
        }
    }
    let rgb = img.chunks(channels).map(|p| [p[0], p[1], p[2]]).collect();
    Png { width, height, rgb }
}

struct Bits<'a> {
    data: &'a [u8],
    pos: usize,
    bit: u32,
}

impl Bits<'_> {
    fn bits(&mut self, n: u32) -> usize {
        let mut v = 0;
        for i in 0..n {
            let b = (self.data[self.pos] >> self.bit) & 1;
            v |= (b as usize) << i;
            self.bit += 1;
            if self.bit == 8 {
                self.bit = 0;
                self.pos += 1;
            }
        }
        v
    }

    fn decode(&mut self, h: &Huffman) -> usize {
        let (mut code, mut first, mut index) = (0usize, 0usize, 0usize);
        for len in 1..16 {
            code |= self.bits(1);
            let count = h.count[len];
            if code < first + count {
                return h.symbol[index + code - first];
            }
            index += count;
            first = (first + count) << 1;
            code <<= 1;
        }
        panic!("bad Huffman code");
    }
}

struct Huffman {
    count: [usize; 16],
    symbol: Vec<usize>,
}

impl Huffman {
    fn new(lengths: &[usize]) -> Self {
        let mut count = [0; 16];
        for &l in lengths {
            count[l] += 1;
        }
        count[0] = 0;
        let mut offs = [0; 16];
        for l in 1..15 {
            offs[l + 1] = offs[l] + count[l];
        }
        let mut symbol = vec![0; lengths.len()];
        for (s, &l) in lengths.iter().enumerate() {
            if l != 0 {
                symbol[offs[l]] = s;
                offs[l] += 1;
            }
        }
        Self { count, symbol }
    }
}

/// Raw DEFLATE (RFC 1951), enough for a test.
fn inflate(data: &[u8]) -> Vec<u8> {
    const LBASE: [usize; 29] = [
        3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115,
        131, 163, 195, 227, 258,
    ];
    const LEXT: [u32; 29] = [
        0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
    ];
    const DBASE: [usize; 30] = [
        1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537,
        2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577,
    ];
    const DEXT: [u32; 30] = [
        0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12,
        13, 13,
    ];
    const ORDER: [usize; 19] = [
        16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
    ];
    let mut out = Vec::new();
    let mut r = Bits {
        data,
        pos: 0,
        bit: 0,
    };
    loop {
        let last = r.bits(1);
        let (lit, dist) = match r.bits(2) {
            0 => {
                if r.bit != 0 {
                    r.bit = 0;
                    r.pos += 1;
                }
                let len = data[r.pos] as usize | (data[r.pos + 1] as usize) << 8;
                out.extend_from_slice(&data[r.pos + 4..r.pos + 4 + len]);
                r.pos += 4 + len;
                if last == 1 {
                    return out;
                }
                continue;
            }
            1 => {
                let mut l = vec![8; 288];
                l[144..256].fill(9);
                l[256..280].fill(7);
                (Huffman::new(&l), Huffman::new(&[5; 30]))
            }
            2 => {
                let (nlen, ndist, ncode) = (r.bits(5) + 257, r.bits(5) + 1, r.bits(4) + 4);
                let mut cl = [0; 19];
                for &o in &ORDER[..ncode] {
                    cl[o] = r.bits(3);
                }
                let ch = Huffman::new(&cl);
                let mut lengths = Vec::with_capacity(nlen + ndist);
                while lengths.len() < nlen + ndist {
                    match r.decode(&ch) {
                        s @ 0..=15 => lengths.push(s),
                        16 => {
                            let prev = *lengths.last().unwrap();
                            let n = 3 + r.bits(2);
                            lengths.extend(std::iter::repeat_n(prev, n));
                        }
                        17 => {
                            let n = 3 + r.bits(3);
                            lengths.extend(std::iter::repeat_n(0, n));
                        }
                        _ => {
                            let n = 11 + r.bits(7);
                            lengths.extend(std::iter::repeat_n(0, n));
                        }
                    }
                }
                (
                    Huffman::new(&lengths[..nlen]),
                    Huffman::new(&lengths[nlen..]),
                )
            }
            _ => panic!("bad DEFLATE block type"),
        };
        loop {
            let s = r.decode(&lit);
            if s < 256 {
                out.push(s as u8);
            } else if s == 256 {
                break;
            } else {
                let len = LBASE[s - 257] + r.bits(LEXT[s - 257]);
                let d = r.decode(&dist);
                let back = DBASE[d] + r.bits(DEXT[d]);
                let start = out.len() - back;
                for k in 0..len {
                    out.push(out[start + k]);
                }
            }
        }
        if last == 1 {
            return out;
        }
    }
}

pub fn distinct_colours(png: &Png) -> usize {
    png.rgb.iter().collect::<HashSet<_>>().len()
}

pub fn field_of(err: OutputError) -> &'static str {
    match err {
        OutputError::Invalid { field, .. } => field,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

/// Steps an MPM model (2D, `D = 4`, or 3D, `D = 6`) from its particles for `steps` steps
/// of `h`, each converged to `tolerance` (`name` in the messages): the final particles.
pub fn mpm_run_to_end<const D: usize>(
    model: &talus::model::mpm::MpmModel<D>,
    steps: usize,
    h: f64,
    tolerance: f64,
    name: &str,
) -> talus_mpm::Particles<D>
where
    talus_mpm::Mandel<D>: talus_mpm::Dimension,
{
    let mut stepper = talus_engine::Stepper::new(&model.mpm, model.step_settings);
    let mut state = talus_mpm::MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    for step in 0..steps {
        let report = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("{name}, step {step}: {e}"));
        assert!(
            report.relative_residual <= tolerance,
            "{name}, step {step}: residual {:e}",
            report.relative_residual
        );
    }
    state.particles
}

/// The shipped 3D MPM scene `scenes/<name>`, read by `SceneFile` as `talus run` reads it.
pub fn shipped_mpm_scene_3d(name: &str) -> talus::scene::MpmScene3 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    match talus::scene::SceneFile::from_path(&path).unwrap_or_else(|e| panic!("{e}")) {
        talus::scene::SceneFile::Mpm3(s) => s,
        _ => panic!("{name} is not a 3D MPM scene"),
    }
}
