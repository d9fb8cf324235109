//! `spar plan`: job scripts that render a scene as `N` tiles and merge
//! them — a Slurm submission script (a job array plus a merge job that
//! depends on it) or an Open Job Description template.
//!
//! Every path is made absolute when the plan is made: jobs run in other
//! directories. The tile count is written into each command (`--tile
//! I/N`), never taken from the farm: a resubmitted single array task sees
//! `SLURM_ARRAY_TASK_COUNT=1`.

use std::path::Path;

/// What the job renders and where it writes.
#[derive(Clone, Debug)]
pub struct Plan<'a> {
    /// The spar binary the jobs run.
    pub spar: &'a Path,
    pub scene: &'a Path,
    /// Directory for parts, logs, the merged raw file and the images.
    pub out_dir: &'a Path,
    pub tiles: u32,
    /// Extra `spar render` arguments every tile takes (overrides, modes,
    /// ISA), already split into words.
    pub render_args: Vec<String>,
    /// Modes and wavelength for `spar develop`, as arguments.
    pub develop_args: Vec<String>,
    /// Threads per tile (Slurm: CPUs per task).
    pub threads: u32,
    /// Slurm partition and time limit, passed to sbatch when given.
    pub partition: Option<String>,
    pub time: Option<String>,
    /// Name of the final image (under `out_dir`), e.g. `image.png`.
    pub image: String,
}

/// `s` quoted for a POSIX shell (single quotes).
pub fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-,:=+@%".contains(&b))
    {
        return s.to_string();
    }
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn words(list: &[String]) -> String {
    list.iter()
        .map(|w| shell_quote(w))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Plan<'_> {
    fn p(&self, path: &Path) -> String {
        path.to_string_lossy().into_owned()
    }

    /// A bash script that submits the tiles as a Slurm job array and the
    /// merge as a job that runs when they have all succeeded. With an
    /// argument (`3` or `3,7` or `2-5`) it submits only those tiles, and
    /// the merge again.
    pub fn slurm(&self) -> String {
        let n = self.tiles;
        let spar = shell_quote(&self.p(self.spar));
        let scene = shell_quote(&self.p(self.scene));
        let out = self.p(self.out_dir);
        let q = |rel: &str| shell_quote(&format!("{out}/{rel}"));
        let mut sbatch_common = format!("--ntasks=1 --cpus-per-task={}", self.threads);
        if let Some(p) = &self.partition {
            sbatch_common += &format!(" --partition={}", shell_quote(p));
        }
        if let Some(t) = &self.time {
            sbatch_common += &format!(" --time={}", shell_quote(t));
        }
        let extra = words(&self.render_args);
        let develop = words(&self.develop_args);
        let parts = format!(
            "{}{{0..{}}}{}",
            q("parts/tile-"),
            n - 1,
            shell_quote(".exr")
        );
        format!(
            r#"#!/bin/bash
# A spar render farm job for Slurm, made by `spar plan` (spar {version}).
# Scene {scene_txt}: {n} tiles; output in {out}.
#
#   bash this-script          submit every tile (a job array) and the merge
#   bash this-script 3,7      submit tiles 3 and 7 again (after a failure),
#                             and the merge again
#
# Tile I runs `spar render --tile I/{n}` and writes parts/tile-I.exr; the
# merge job waits for every tile of its submission to succeed (afterok) and
# is cancelled if one fails. It merges all {n} parts into merged.exr and
# develops {image}. Logs: logs/. A tile stopped by SIGTERM (scancel, time
# limit) saves a checkpoint that the next run of that tile resumes.
set -euo pipefail
OUT={out_q}
TILES="${{1:-0-{last}}}"
mkdir -p "$OUT/parts" "$OUT/logs"
array=$(sbatch --parsable --job-name=spar-tiles --array="$TILES" {common} \
    --output="$OUT/logs/tile-%a.log" <<'SPAR_TILE'
#!/bin/bash
exec {spar} render {scene} --tile "$SLURM_ARRAY_TASK_ID/{n}" \
    --threads "${{SLURM_CPUS_PER_TASK:-1}}" --progress plain --resume \
    -o {parts_dir}"/tile-$SLURM_ARRAY_TASK_ID.exr"{extra_sep}{extra}
SPAR_TILE
)
array=${{array%%;*}}
merge=$(sbatch --parsable --job-name=spar-merge --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes {common} --output="$OUT/logs/merge.log" <<'SPAR_MERGE'
#!/bin/bash
set -euo pipefail
{spar} merge {parts} -o {merged} --progress plain
exec {spar} develop {merged} {develop} -o {image_q} --progress plain
SPAR_MERGE
)
merge=${{merge%%;*}}
echo "spar: submitted tiles $TILES as job $array and the merge as job $merge"
"#,
            version = crate::VERSION,
            scene_txt = self.p(self.scene),
            out_q = shell_quote(&out),
            last = n - 1,
            common = sbatch_common,
            parts_dir = q("parts"),
            extra_sep = if extra.is_empty() { "" } else { " \\\n    " },
            merged = q("merged.exr"),
            image_q = q(&self.image),
            image = self.image,
        )
    }

    /// An Open Job Description job template (YAML): a step with one task
    /// per tile and a merge step that depends on it.
    pub fn openjd(&self) -> String {
        let n = self.tiles;
        // YAML: every scalar in double quotes with JSON escaping (JSON
        // strings are YAML strings).
        let y = |s: &str| serde_json::to_string(s).expect("strings serialize");
        let extra = words(&self.render_args);
        let develop = words(&self.develop_args);
        let stem = self
            .scene
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        format!(
            r#"# A spar render farm job as an Open Job Description template, made by
# `spar plan` (spar {version}): {n} tiles of {scene_txt}, then a merge.
specificationVersion: 'jobtemplate-2023-09'
name: {name}
parameterDefinitions:
- name: Spar
  type: STRING
  description: The spar executable on the workers.
  default: {spar}
- name: SceneFile
  type: PATH
  objectType: FILE
  dataFlow: IN
  default: {scene}
- name: OutputDir
  type: PATH
  objectType: DIRECTORY
  dataFlow: OUT
  default: {out}
steps:
- name: RenderTiles
  parameterSpace:
    taskParameterDefinitions:
    - name: Tile
      type: INT
      range: "0-{last}"
  script:
    actions:
      onRun:
        command: bash
        args: ["{{{{Task.File.Run}}}}"]
    embeddedFiles:
    - name: Run
      type: TEXT
      data: |
        set -euo pipefail
        mkdir -p '{{{{Param.OutputDir}}}}/parts'
        exec '{{{{Param.Spar}}}}' render '{{{{Param.SceneFile}}}}' --tile '{{{{Task.Param.Tile}}}}/{n}' \
          --threads {threads} --progress openjd --resume \
          -o '{{{{Param.OutputDir}}}}/parts/tile-{{{{Task.Param.Tile}}}}.exr'{extra_sep}{extra}
- name: Merge
  dependencies:
  - dependsOn: RenderTiles
  script:
    actions:
      onRun:
        command: bash
        args: ["{{{{Task.File.Run}}}}"]
    embeddedFiles:
    - name: Run
      type: TEXT
      data: |
        set -euo pipefail
        cd '{{{{Param.OutputDir}}}}'
        '{{{{Param.Spar}}}}' merge parts/tile-{{0..{last}}}.exr -o merged.exr --progress openjd
        exec '{{{{Param.Spar}}}}' develop merged.exr {develop} -o {image} --progress openjd
"#,
            version = crate::VERSION,
            scene_txt = self.p(self.scene),
            name = y(&format!("spar {stem} ({n} tiles)")),
            spar = y(&self.p(self.spar)),
            scene = y(&self.p(self.scene)),
            out = y(&self.p(self.out_dir)),
            last = n - 1,
            threads = self.threads,
            extra_sep = if extra.is_empty() {
                ""
            } else {
                " \\\n          "
            },
            image = shell_quote(&self.image),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting() {
        assert_eq!(shell_quote("/a/b-c.exr"), "/a/b-c.exr");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
        assert_eq!(shell_quote(""), "''");
        assert_eq!(shell_quote("$HOME"), "'$HOME'");
    }
}
