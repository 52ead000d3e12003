//! Which files a run writes, and the rules they must pass before it starts: no output
//! over an input (the config, a table, the checkpoint resumed from), none over another
//! output of the same run, none but regular files or new paths, and none that another
//! run holds locked.

use anyhow::{Result, bail};
use emdstar_system::{CheckpointFile, FileIdentity, OutputConfig, check_writable};
use std::path::{Path, PathBuf};

/// The files a run writes. `None` writes no such file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunFiles {
    pub trajectory: Option<PathBuf>,
    pub log: Option<PathBuf>,
    /// Where checkpoints go when asked for (`--checkpoint`, or `[output]
    /// restart_interval`); `None` if neither asked.
    pub checkpoint: Option<PathBuf>,
    /// Where a stopped run saves its state when no checkpoint was asked for.
    pub stop_checkpoint: PathBuf,
}

impl RunFiles {
    /// The files of a run of the config at `config`: each given path (`trajectory`,
    /// `log`, `checkpoint`: the command line's) over the config's `[output]`, over the
    /// config's stem with `.xyz` and `.log` in the current directory; "none" writes no
    /// trajectory or log. Checkpoints go to `checkpoint`, or with a restart interval
    /// next to the trajectory (else the log, else the config's stem) with `.ckpt`;
    /// a stopped run saves there too.
    pub fn resolve(
        config: &Path,
        output: &OutputConfig,
        trajectory: Option<&Path>,
        log: Option<&Path>,
        checkpoint: Option<&Path>,
    ) -> Self {
        let stem = config
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().into_owned());
        let choose = |arg: Option<&Path>, key: &Option<String>, ext: &str| {
            let path = arg
                .map(Path::to_path_buf)
                .or(key.as_ref().map(PathBuf::from))
                .unwrap_or_else(|| format!("{stem}.{ext}").into());
            (path != Path::new("none")).then_some(path)
        };
        let trajectory = choose(trajectory, &output.trajectory, "xyz");
        let log = choose(log, &output.log, "log");
        let beside = trajectory.as_ref().or(log.as_ref()).map_or_else(
            || PathBuf::from(format!("{stem}.ckpt")),
            |p| p.with_extension("ckpt"),
        );
        let checkpoint = checkpoint
            .map(Path::to_path_buf)
            .or_else(|| output.restart_interval.map(|_| beside.clone()));
        Self {
            stop_checkpoint: checkpoint.clone().unwrap_or(beside),
            trajectory,
            log,
            checkpoint,
        }
    }

    /// The checkpoint path in use: the one asked for, or the stopped run's.
    pub fn checkpoint_path(&self) -> &Path {
        self.checkpoint.as_deref().unwrap_or(&self.stop_checkpoint)
    }

    /// Every file the run writes, named as in messages, with the option that sets it:
    /// the trajectory, the log, the checkpoint and its temporary file.
    fn outputs(&self) -> Vec<(String, PathBuf)> {
        let mut out = Vec::new();
        if let Some(p) = &self.trajectory {
            out.push(("the trajectory (--trajectory)".into(), p.clone()));
        }
        if let Some(p) = &self.log {
            out.push(("the log (--log)".into(), p.clone()));
        }
        let ckpt = self.checkpoint_path();
        out.push(("the checkpoint (--checkpoint)".into(), ckpt.to_path_buf()));
        out.push((
            "the checkpoint's temporary file".into(),
            CheckpointFile::partial_path(ckpt),
        ));
        out
    }

    /// Refuses these outputs unless each is a regular file or a new path, none is
    /// another, and none is one of `inputs` (what each is, for messages, and its path);
    /// the checkpoint may replace the checkpoint the run resumes from (`resume`), which
    /// it continues.
    pub fn check(&self, inputs: &[(&str, &Path)], resume: Option<&Path>) -> Result<()> {
        let outputs = self.outputs();
        let mut seen: Vec<(&str, &Path, FileIdentity)> = Vec::new();
        for (what, path) in &outputs {
            check_writable(path).map_err(|e| {
                let none = ["trajectory", "log"].into_iter().find(|w| what.contains(w));
                match none {
                    Some(w) => anyhow::anyhow!("{e} (--{w} none writes none)"),
                    None => e.into(),
                }
            })?;
            let id = FileIdentity::of(path)?;
            if let Some((other, other_path, _)) = seen.iter().find(|s| s.2 == id) {
                bail!(
                    "{what} and {other} are the same file ({} and {}): give each output its \
                     own path",
                    path.display(),
                    other_path.display()
                );
            }
            seen.push((what, path, id));
        }
        let resume = resume.map(|p| ("the checkpoint resumed from (--resume)", p));
        for (input, input_path) in inputs.iter().copied().chain(resume) {
            let Ok(id) = FileIdentity::of(input_path) else {
                continue;
            };
            for (what, path, out_id) in &seen {
                let continues =
                    Some(input_path) == resume.map(|r| r.1) && *path == self.checkpoint_path();
                if *out_id == id && !continues {
                    bail!(
                        "{what} {} is {input} {}: a run never writes over its inputs; give \
                         the output another path",
                        path.display(),
                        input_path.display()
                    );
                }
            }
        }
        Ok(())
    }
}
