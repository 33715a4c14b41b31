//! Checkpoints (`talus run --checkpoint-every N`) and their reading by `talus resume
//! OUT_DIR` (`docs/scenes.md`, 'Checkpoints and resume'): everything the next step and the
//! outputs depend on, written every N steps to `OUT_DIR/checkpoint/last.checkpoint`.
//!
//! The file is one header line, `talus-checkpoint format=1 step=K bytes=B fnv1a64=X
//! history=Y`, then the checkpoint as JSON (B bytes, FNV-1a 64 hash X): a truncated or
//! altered file is refused, never half read. Y ties it to its folder: the hash of
//! `history.csv`'s header and row K (its wall time aside) when it was written
//! ([`history_key`]); a checkpoint whose Y is not its folder's (another run's, copied
//! there) is refused. JSON because the
//! workspace's serde_json already writes every finite f64 in its shortest round-trip form
//! (ryu) and, with `float_roundtrip`, reads it back to the same bits; no new dependency,
//! and the file can be inspected. Its cost, about 20 bytes per value, is measured in
//! `docs/scenes.md`.
mod resume;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use talus_engine::{CollapseWatch, StepperMemory};

pub use resume::{
    drop_numbered_files, history_key, history_prefix, keep_existing_files, write_history,
};

/// The checkpoint's path in an output folder.
pub fn path(out: &Path) -> PathBuf {
    out.join("checkpoint").join("last.checkpoint")
}

/// The file format written; another is refused.
pub const FORMAT: u32 = 1;

/// What `talus` wrote the checkpoint: version and commit.
pub const WRITER: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("TALUS_COMMIT"),
    ")"
);

/// The scene a checkpoint continues: its file (`None`: the built-in footing), its text and
/// the hash of the text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneRecord {
    pub path: Option<PathBuf>,
    pub source: String,
    pub hash: String,
    /// The text is not the file's (a scene edited in memory, e.g. by the Python package's
    /// `Scene.set`): the checkpoint holds the only copy, and `path` only resolves the
    /// scene's relative paths.
    #[serde(default)]
    pub held: bool,
}

impl SceneRecord {
    pub fn new(path: Option<&Path>, source: &str) -> Self {
        // Absolute, so that `talus resume` finds it from any folder.
        let path = path.map(|p| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()));
        // Without a file, the scene is the built-in footing only if it is its text: an
        // in-memory scene (the Python package's `Scene.from_toml`) is held.
        let held = match &path {
            Some(p) => std::fs::read_to_string(p).ok().as_deref() != Some(source),
            None => source != crate::scene::BUILTIN_FOOTING,
        };
        Self {
            path,
            source: source.to_string(),
            hash: hash_text(source),
            held,
        }
    }
}

/// `fnv1a64:` and the FNV-1a 64-bit hash of `text` in hex.
pub fn hash_text(text: &str) -> String {
    format!("fnv1a64:{:016x}", fnv1a64(text.as_bytes()))
}

/// FNV-1a, 64 bits (Fowler, Noll, Vo): detects a changed scene or a damaged file, not
/// tampering by an adversary.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// How often a run checkpoints, and the scene it writes into its checkpoints.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub every: usize,
    pub scene: SceneRecord,
}

/// The state after step `step` of `steps`, and everything else the next step and the
/// outputs depend on. `S`: the discretization's state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Checkpoint<S> {
    /// The `talus` that wrote it ([`WRITER`]).
    pub talus: String,
    pub scene: SceneRecord,
    /// `--checkpoint-every`: a resumed run goes on checkpointing as often.
    pub every: usize,
    pub step: usize,
    pub steps: usize,
    /// The time step (s).
    pub h: f64,
    pub state: S,
    pub stepper: StepperMemory,
    pub watch: CollapseWatch,
    /// The outputs' own record (`RunOutputs::save`).
    pub outputs: serde_json::Value,
}

/// Why a checkpoint cannot be written or resumed, or an output folder not used
/// (`crate::run::folder`).
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error(
        "no checkpoint in {}: {} not found (a run writes one with `talus run SCENE --checkpoint-every N`)",
        dir.display(),
        path.display()
    )]
    Missing { dir: PathBuf, path: PathBuf },
    #[error("cannot read or write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("checkpoint {} is corrupt ({why}): it cannot be resumed", path.display())]
    Corrupt { path: PathBuf, why: String },
    #[error(
        "the scene {} changed since the checkpoint of step {step} ({now} now, {then} then): \
         resume refused (restore the scene, or run it afresh with `talus run`)",
        scene
    )]
    SceneChanged {
        scene: String,
        step: usize,
        now: String,
        then: String,
    },
    /// The outputs beside the checkpoint do not reach it (e.g. a `history.csv` shorter than
    /// the checkpoint's step).
    #[error("{}: {why}: it cannot be resumed from the checkpoint of step {step}", path.display())]
    Outputs {
        path: PathBuf,
        step: usize,
        why: String,
    },
    /// The checkpoint was not written after the rows of `history.csv` beside it: another
    /// run's checkpoint copied into the folder, or `history.csv` replaced.
    #[error(
        "checkpoint {} is not the one of the run in {}: it was written after another row of \
         step {step} than the one in history.csv (another run's checkpoint, or history.csv \
         replaced): resume refused, nothing in the folder was changed (run the scene afresh \
         with `talus run`)",
        path.display(),
        dir.display()
    )]
    Foreign {
        dir: PathBuf,
        path: PathBuf,
        step: usize,
    },
    /// Another run or resume holds the output folder (`crate::run::folder::lock`).
    #[error(
        "the output folder {} is in use by another talus run or resume{holder}: refused, \
         nothing in it was changed (wait for that run to end, or choose another folder; its \
         lock is {})",
        dir.display(),
        lock.display()
    )]
    InUse {
        dir: PathBuf,
        lock: PathBuf,
        /// ` (pid N)`, or empty when the holder's pid is not known.
        holder: String,
    },
}

impl CheckpointError {
    fn corrupt(path: &Path, why: impl Into<String>) -> Self {
        Self::Corrupt {
            path: path.to_path_buf(),
            why: why.into(),
        }
    }

    /// Whether the cause is the file system (exit 5) rather than the folder's content
    /// (exit 1).
    pub fn is_io(&self) -> bool {
        matches!(self, CheckpointError::Io { .. })
    }
}

/// Writes `checkpoint` to `out`'s checkpoint file, atomically: a kill while writing leaves
/// the previous checkpoint. Its header ties it to `out/history.csv`, whose last row is then
/// the checkpoint's step ([`history_key`]; none when it is not).
pub fn write<S: Serialize>(out: &Path, checkpoint: &Checkpoint<S>) -> Result<(), CheckpointError> {
    let path = path(out);
    let io = |source| CheckpointError::Io {
        path: path.clone(),
        source,
    };
    let payload = serde_json::to_vec(checkpoint).map_err(|e| io(std::io::Error::other(e)))?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let history = resume::key_of_file(&out.join("history.csv"), checkpoint.step)
        .map_or(String::new(), |key| format!(" history={key}"));
    let mut bytes = format!(
        "talus-checkpoint format={FORMAT} step={} bytes={} fnv1a64={:016x}{history}\n",
        checkpoint.step,
        payload.len(),
        fnv1a64(&payload)
    )
    .into_bytes();
    bytes.extend_from_slice(&payload);
    crate::output::write_atomically(&path, bytes).map_err(|e| match e {
        crate::output::OutputError::Io { source, .. } => io(source),
        other => io(std::io::Error::other(other.to_string())),
    })
}

/// The step of `out`'s checkpoint, from its header alone (`None`: no checkpoint).
pub fn step_of(out: &Path) -> Option<usize> {
    let text = std::fs::read(path(out)).ok()?;
    let end = text.iter().position(|&b| b == b'\n')?;
    let header = std::str::from_utf8(&text[..end]).ok()?;
    field(header, "step")?.parse().ok()
}

fn field<'a>(header: &'a str, name: &str) -> Option<&'a str> {
    header
        .split(' ')
        .find_map(|w| w.strip_prefix(name)?.strip_prefix('='))
}

/// Reads `out`'s checkpoint, its state left as JSON for the method to read
/// ([`Checkpoint::with_state`]). Every damage the header can reveal (length, hash,
/// format) is an error naming it; so are a `history.csv` that does not reach its step and,
/// when the header has its `history` key, one whose row of the step is not the one it was
/// written after (another run's checkpoint). Reads only.
pub fn read(out: &Path) -> Result<Checkpoint<serde_json::Value>, CheckpointError> {
    let path = path(out);
    let bytes = std::fs::read(&path).map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            CheckpointError::Missing {
                dir: out.to_path_buf(),
                path: path.clone(),
            }
        } else {
            CheckpointError::Io {
                path: path.clone(),
                source,
            }
        }
    })?;
    let end = bytes
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| CheckpointError::corrupt(&path, "no header line"))?;
    let header = std::str::from_utf8(&bytes[..end])
        .ok()
        .filter(|h| h.starts_with("talus-checkpoint "))
        .ok_or_else(|| {
            CheckpointError::corrupt(&path, "its first line is not a talus-checkpoint header")
        })?;
    let number = |name: &str| {
        field(header, name)
            .ok_or_else(|| CheckpointError::corrupt(&path, format!("its header has no {name}")))
    };
    let format = number("format")?;
    if format != FORMAT.to_string() {
        return Err(CheckpointError::corrupt(
            &path,
            format!("format {format}, this talus reads format {FORMAT}"),
        ));
    }
    let payload = &bytes[end + 1..];
    let expected = number("bytes")?;
    if expected != payload.len().to_string() {
        return Err(CheckpointError::corrupt(
            &path,
            format!(
                "{} bytes after the header, {expected} announced",
                payload.len()
            ),
        ));
    }
    let hash = format!("{:016x}", fnv1a64(payload));
    let announced = number("fnv1a64")?;
    if hash != announced {
        return Err(CheckpointError::corrupt(
            &path,
            format!("content hash {hash}, {announced} written"),
        ));
    }
    let checkpoint: Checkpoint<serde_json::Value> = serde_json::from_slice(payload)
        .map_err(|e| CheckpointError::corrupt(&path, e.to_string()))?;
    if checkpoint.scene.hash != hash_text(&checkpoint.scene.source) {
        return Err(CheckpointError::corrupt(
            &path,
            "the scene text does not match its hash",
        ));
    }
    if checkpoint.every == 0 || checkpoint.step > checkpoint.steps {
        return Err(CheckpointError::corrupt(
            &path,
            format!(
                "step {} of {} every {}",
                checkpoint.step, checkpoint.steps, checkpoint.every
            ),
        ));
    }
    let history = out.join("history.csv");
    match field(header, "history") {
        Some(key) => {
            let kept = history_prefix(&history, checkpoint.step)?;
            if resume::key_of_prefix(&kept).as_deref() != Some(key) {
                return Err(CheckpointError::Foreign {
                    dir: out.to_path_buf(),
                    path,
                    step: checkpoint.step,
                });
            }
        }
        None => tracing::warn!(
            checkpoint = %path.display(),
            "the checkpoint does not record the history.csv it was written after (an older \
             talus wrote it): that it is this folder's run cannot be checked"
        ),
    }
    if checkpoint.talus != WRITER {
        tracing::warn!(
            written_by = checkpoint.talus,
            resumed_by = WRITER,
            "the checkpoint was written by another talus: the resumed steps may differ in the \
             last bits from the run it continues"
        );
    }
    Ok(checkpoint)
}

impl Checkpoint<serde_json::Value> {
    /// The checkpoint with its state read as `S`.
    pub fn with_state<S: serde::de::DeserializeOwned>(
        self,
        out: &Path,
    ) -> Result<Checkpoint<S>, CheckpointError> {
        let state = serde_json::from_value(self.state).map_err(|e| {
            CheckpointError::corrupt(&path(out), format!("its state is not this method's: {e}"))
        })?;
        Ok(Checkpoint {
            talus: self.talus,
            scene: self.scene,
            every: self.every,
            step: self.step,
            steps: self.steps,
            h: self.h,
            state,
            stepper: self.stepper,
            watch: self.watch,
            outputs: self.outputs,
        })
    }

    /// The scene to resume: the file the checkpoint names, refused when its text is not
    /// the checkpoint's (the built-in footing: this `talus`'s; a held scene: the
    /// checkpoint's own text). Its text is returned.
    pub fn current_scene(&self) -> Result<String, CheckpointError> {
        let (name, now) = match &self.scene.path {
            // Its text was checked against its hash when the checkpoint was read.
            _ if self.scene.held => return Ok(self.scene.source.clone()),
            Some(p) => (
                p.display().to_string(),
                std::fs::read_to_string(p).map_err(|source| CheckpointError::Io {
                    path: p.clone(),
                    source,
                })?,
            ),
            None => (
                "(built-in footing)".to_string(),
                crate::scene::BUILTIN_FOOTING.to_string(),
            ),
        };
        let hash = hash_text(&now);
        if hash != self.scene.hash {
            return Err(CheckpointError::SceneChanged {
                scene: name,
                step: self.step,
                now: hash,
                then: self.scene.hash.clone(),
            });
        }
        Ok(now)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values whose shortest decimal form is hardest to read back: subnormals, the
    /// extremes, −0, neighbours of powers of two and of halfway cases, and a sweep of bit
    /// patterns.
    #[test]
    fn every_finite_f64_comes_back_with_its_bits() {
        let mut values = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE / 3.0,
            f64::from_bits(1),
            f64::from_bits(0x000f_ffff_ffff_ffff),
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1.0 + f64::EPSILON,
            0.1 + 0.2,
            9007199254740993.0,
            5e-324,
            f64::from_bits(0x0010_0000_0000_0001),
            1.7976931348623157e308,
        ];
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..20_000 {
            // xorshift64*: bit patterns across every exponent.
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            let v = f64::from_bits(x.wrapping_mul(0x2545_f491_4f6c_dd1d));
            if v.is_finite() {
                values.push(v);
            }
        }
        let text = serde_json::to_string(&values).unwrap();
        let back: Vec<f64> = serde_json::from_str(&text).unwrap();
        let back_value: Vec<f64> =
            serde_json::from_value(serde_json::from_str::<serde_json::Value>(&text).unwrap())
                .unwrap();
        for ((a, b), c) in values.iter().zip(&back).zip(&back_value) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a:e} read back as {b:e}");
            assert_eq!(
                a.to_bits(),
                c.to_bits(),
                "{a:e} read back as {c:e} by Value"
            );
        }
    }

    #[test]
    fn fnv1a64_matches_its_published_vectors() {
        // The reference vectors of the FNV authors (isthe.com/chongo/tech/comp/fnv).
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }
}
