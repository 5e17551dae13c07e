//! The output of a run step by step ("many load steps in flat
//! memory"): at the end of each load step the root hands its contact.csv
//! rows and, when the scene writes that step's fields (`[output] steps`),
//! every body's fields to a [`StepSink`], and forgets them. [`FieldWriter`]
//! streams them to disk (the VTU piece of each body, its `fields.pvd` entry,
//! the contact.csv lines; with `[output] pieces`, the subdomains' pieces
//! and their `.pvtu` index, see [`crate::pieces`]); [`StepsInMemory`] keeps
//! them (the library's `run`, for tests and callers that want the whole
//! history).
//!
//! A [`FieldWriter`] writes into a staging directory inside the output
//! directory and moves its files into place only when the run has ended
//! ([`FieldWriter::commit`]): a run that fails part-way (bad input met at
//! step k, exit 1) leaves nothing behind, and a run solved again (a widened
//! candidate zone) starts from an empty stage.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::pieces::{piece_file, ContactFields, NodalContact, SubdomainPiece};
use crate::results::{BodyResult, OutputRequest, RunOutput, StepFields};
use crate::vtu::{
    declared_arrays, write_pvd, write_pvtu, write_vtu, PvdEntry, VtuPiece, NODE_ARRAY,
};
use crate::ContactRow;

/// What a load step that ended sends to its [`StepSink`].
#[derive(Clone, Copy)]
pub struct StepResults<'a> {
    /// The load step, 1-based.
    pub step: usize,
    /// The bodies' meshes (their `history` is not read).
    pub bodies: &'a [BodyResult],
    /// When the scene writes this step's fields: every body's fields.
    pub fields: Option<&'a [StepFields]>,
    /// Its contact.csv rows.
    pub rows: &'a [ContactRow],
}

/// Where the root sends each load step's results as the step ends.
pub trait StepSink {
    /// A load step ended with `results`.
    fn step(&mut self, results: StepResults<'_>) -> Result<(), String>;

    /// The run starts again from its first step (the candidate zone was
    /// widened): forget the steps received so far.
    fn restart(&mut self);

    /// On the root, before the first step, when the ranks write pieces
    /// (`[output] pieces`): every subdomain as (body, part), whose pieces
    /// the index of each step that writes fields names.
    fn pieces_of(&mut self, _subdomains: &[(usize, usize)]) {}

    /// One subdomain's piece at load step `step`, on the rank that owns it.
    fn piece(&mut self, _step: usize, _piece: &SubdomainPiece) -> Result<(), String> {
        Ok(())
    }
}

/// Keeps every step in memory: the contact rows, and the fields of the
/// steps that write them.
#[derive(Default)]
pub struct StepsInMemory {
    pub rows: Vec<ContactRow>,
    /// Per step that wrote fields: each body's fields.
    pub fields: Vec<Vec<StepFields>>,
}

impl StepSink for StepsInMemory {
    fn step(&mut self, results: StepResults<'_>) -> Result<(), String> {
        self.rows.extend_from_slice(results.rows);
        if let Some(f) = results.fields {
            self.fields.push(f.to_vec());
        }
        Ok(())
    }

    fn restart(&mut self) {
        *self = Self::default();
    }
}

impl StepsInMemory {
    /// Puts the kept steps into the run's output: every contact row, and
    /// each body's history of fields (left as it is when no step wrote any).
    pub fn fill(self, output: &mut RunOutput) {
        output.contact_rows = self.rows;
        if self.fields.is_empty() {
            return;
        }
        for b in &mut output.bodies {
            b.history.clear();
        }
        for step in self.fields {
            for (b, f) in output.bodies.iter_mut().zip(step) {
                b.history.push(f);
            }
        }
    }
}

/// Streams each step to the output directory: contact.csv line by line,
/// and the VTU piece of every body at the steps that write fields.
pub struct FieldWriter {
    dir: PathBuf,
    request: OutputRequest,
    /// The staging directory, once the first step created it.
    stage: Option<PathBuf>,
    /// The outermost directory this writer created (removed again, if still
    /// empty, when the run does not commit).
    created: Option<PathBuf>,
    contact: Option<BufWriter<File>>,
    entries: Vec<PvdEntry>,
    /// (body, part) of every subdomain whose pieces the index names (the
    /// root, `[output] pieces`).
    subdomains: Vec<(usize, usize)>,
    /// The `.pvtu` indexes written, for `pieces.pvd`.
    index_entries: Vec<PvdEntry>,
    /// The pieces those indexes name (`pieces/…`, whichever rank writes them).
    sources: Vec<String>,
    committed: bool,
}

impl FieldWriter {
    /// A writer into `dir` (created at the first step).
    pub fn new(dir: &Path, request: OutputRequest) -> Self {
        FieldWriter {
            dir: dir.to_path_buf(),
            request,
            stage: None,
            created: None,
            contact: None,
            entries: Vec::new(),
            subdomains: Vec::new(),
            index_entries: Vec::new(),
            sources: Vec::new(),
            committed: false,
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    pub fn request(&self) -> &OutputRequest {
        &self.request
    }

    /// The staging directory, created with the output directory on first use.
    fn stage(&mut self) -> std::io::Result<PathBuf> {
        if let Some(s) = &self.stage {
            return Ok(s.clone());
        }
        if self.created.is_none() {
            self.created = self
                .dir
                .ancestors()
                .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
                .last()
                .map(Path::to_path_buf);
        }
        let stage = self
            .dir
            .join(format!(".signorini-steps-{}", std::process::id()));
        std::fs::create_dir_all(&stage)?;
        self.stage = Some(stage.clone());
        Ok(stage)
    }

    /// Writes one step (see [`StepSink::step`]).
    fn write_step(&mut self, results: StepResults<'_>) -> Result<(), String> {
        let StepResults {
            step,
            bodies,
            fields,
            rows,
        } = results;
        let stage = self.stage().map_err(|e| e.to_string())?;
        let dim = self.request.dim;
        if self.contact.is_none() {
            let mut w = BufWriter::new(File::create(stage.join("contact.csv")).map_err(err)?);
            crate::write_contact_header(&mut w, dim).map_err(err)?;
            self.contact = Some(w);
        }
        if let Some(w) = self.contact.as_mut() {
            for r in rows {
                crate::write_contact_row(w, r, dim).map_err(err)?;
            }
        }
        if let (Some(fields), false) = (fields, self.request.fields.is_empty()) {
            let nodal = NodalContact::of_rows(rows, step);
            for (bi, (b, f)) in bodies.iter().zip(fields).enumerate() {
                let file = format!("{}_{step}.vtu", b.file_stem);
                let contact = ContactFields::of(&nodal, &b.name, b.coords.len(), Some);
                let piece = vtu_piece(&self.request, b, f, &contact);
                write_vtu(&stage.join(&file), &piece)?;
                self.entries.push(PvdEntry {
                    timestep: step as f64,
                    part: bi,
                    file,
                });
                self.write_index(&stage, step, bi, &b.file_stem, &piece)?;
            }
        }
        Ok(())
    }

    /// The `.pvtu` index of body `bi` (file stem `name`) at `step` naming
    /// its subdomains' pieces, with the arrays of its gathered piece `whole`
    /// and `node`.
    fn write_index(
        &mut self,
        stage: &Path,
        step: usize,
        bi: usize,
        name: &str,
        whole: &VtuPiece<'_>,
    ) -> Result<(), String> {
        if self.subdomains.is_empty() {
            return Ok(());
        }
        let sources: Vec<String> = (self.subdomains.iter())
            .filter(|(b, _)| *b == bi)
            .map(|&(_, part)| piece_file(name, step, part))
            .collect();
        let mut arrays = declared_arrays(whole);
        arrays[0].push((NODE_ARRAY.to_string(), 1, "UInt64"));
        let file = format!("{name}_{step}.pvtu");
        write_pvtu(&stage.join(&file), &arrays, &sources).map_err(err)?;
        self.sources.extend(sources);
        self.index_entries.push(PvdEntry {
            timestep: step as f64,
            part: bi,
            file,
        });
        Ok(())
    }

    /// Writes one subdomain's piece (see [`StepSink::piece`]).
    fn write_piece(&mut self, step: usize, p: &SubdomainPiece) -> Result<(), String> {
        let stage = self.stage().map_err(err)?;
        let file = piece_file(&p.mesh.file_stem, step, p.part);
        let path = stage.join(&file);
        if let Some(d) = path.parent() {
            std::fs::create_dir_all(d).map_err(err)?;
        }
        let mut piece = vtu_piece(&self.request, &p.mesh, &p.fields, &p.contact);
        piece.node_ids = Some(&p.nodes);
        write_vtu(&path, &piece)
    }

    /// Moves the staged files into the output directory and writes
    /// `fields.pvd` (body after body, step after step) when any step wrote
    /// fields, and `pieces.pvd` when any step wrote a `.pvtu` index;
    /// contact.csv is written (its header alone) even when no step ran.
    pub fn commit(&mut self) -> std::io::Result<()> {
        let stage = self.stage()?;
        if let Some(mut w) = self.contact.take() {
            w.flush()?;
        } else {
            crate::write_contact_csv(&stage.join("contact.csv"), &[], self.request.dim)?;
        }
        self.move_staged(&stage)?;
        if !self.request.fields.is_empty() {
            self.entries.sort_by_key(|e| (e.part, e.timestep as u64));
            write_pvd(&self.dir.join("fields.pvd"), &self.entries)?;
        }
        if !self.index_entries.is_empty() {
            self.index_entries
                .sort_by_key(|e| (e.part, e.timestep as u64));
            write_pvd(&self.dir.join("pieces.pvd"), &self.index_entries)?;
        }
        Ok(())
    }

    /// The files of the output directory that the steps wrote (relative
    /// to it): the bodies' VTU files, their `.pvtu` indexes, the pieces
    /// these name and the `.pvd` series.
    pub fn written(&self) -> std::collections::BTreeSet<String> {
        let mut files: std::collections::BTreeSet<String> = (self.entries.iter())
            .chain(&self.index_entries)
            .map(|e| e.file.clone())
            .chain(self.sources.iter().cloned())
            .collect();
        if !self.request.fields.is_empty() {
            files.insert("fields.pvd".into());
        }
        if !self.index_entries.is_empty() {
            files.insert("pieces.pvd".into());
        }
        files
    }

    /// On a rank other than the root, once the run has ended: moves the
    /// pieces it wrote (if any) into `DIR/pieces`.
    pub fn commit_pieces(&mut self) -> std::io::Result<()> {
        match self.stage.clone() {
            Some(stage) => self.move_staged(&stage),
            None => {
                self.committed = true;
                Ok(())
            }
        }
    }

    /// Moves the files of the stage into the output directory (those of its
    /// `pieces` directory into `DIR/pieces`, beside the other ranks' ones)
    /// and removes the stage.
    fn move_staged(&mut self, stage: &Path) -> std::io::Result<()> {
        for entry in std::fs::read_dir(stage)? {
            let entry = entry?;
            let target = self.dir.join(entry.file_name());
            if entry.file_type()?.is_dir() {
                std::fs::create_dir_all(&target)?;
                for file in std::fs::read_dir(entry.path())? {
                    let file = file?;
                    std::fs::rename(file.path(), target.join(file.file_name()))?;
                }
                std::fs::remove_dir(entry.path())?;
            } else {
                std::fs::rename(entry.path(), target)?;
            }
        }
        std::fs::remove_dir(stage)?;
        self.stage = None;
        self.committed = true;
        Ok(())
    }
}

impl StepSink for FieldWriter {
    fn step(&mut self, results: StepResults<'_>) -> Result<(), String> {
        self.write_step(results)
            .map_err(|e| format!("cannot write the output in {}: {e}", self.dir.display()))
    }

    fn restart(&mut self) {
        self.contact = None;
        self.entries.clear();
        self.subdomains.clear();
        self.index_entries.clear();
        self.sources.clear();
        if let Some(stage) = self.stage.take() {
            let _ = std::fs::remove_dir_all(stage);
        }
    }

    fn pieces_of(&mut self, subdomains: &[(usize, usize)]) {
        if !self.request.fields.is_empty() {
            self.subdomains = subdomains.to_vec();
        }
    }

    fn piece(&mut self, step: usize, piece: &SubdomainPiece) -> Result<(), String> {
        if self.request.fields.is_empty() {
            return Ok(());
        }
        self.write_piece(step, piece)
            .map_err(|e| format!("cannot write the output in {}: {e}", self.dir.display()))
    }
}

impl Drop for FieldWriter {
    /// A run that did not commit leaves nothing: the stage is removed, and
    /// the directories this writer created if they are empty.
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        self.restart();
        if let Some(top) = &self.created {
            for d in self.dir.ancestors() {
                if std::fs::remove_dir(d).is_err() || d == top.as_path() {
                    break;
                }
            }
        }
    }
}

fn err(e: std::io::Error) -> String {
    e.to_string()
}

/// The VTU piece of one body at one step with the fields that
/// `[output] fields` asks for: displacement; contact pressure, status (−1 no
/// contact point, 0 open, 1 contact, 2 stick, 3 slip) and tangential force at
/// the slave nodes (from the step's contact rows); stress (Voigt
/// [xx, yy, zz, xy, yz, xz]; axisymmetric: x = r, y = z, zz = hoop) and von
/// Mises per cell; the METIS subdomain of each cell.
fn vtu_piece<'a>(
    request: &OutputRequest,
    b: &'a BodyResult,
    fields: &StepFields,
    contact: &ContactFields,
) -> VtuPiece<'a> {
    let (dim, n) = (request.dim, b.coords.len());
    let mut point_data = Vec::new();
    if request.wants("displacement") {
        let u: Vec<f64> = (0..n)
            .flat_map(|i| {
                let mut v = [0.0; 3];
                v[..dim].copy_from_slice(&fields.displacement[dim * i..dim * (i + 1)]);
                v
            })
            .collect();
        point_data.push(("displacement".to_string(), 3, u));
    }
    if request.wants("contact") {
        point_data.push(("contact_pressure".to_string(), 1, contact.pressure.clone()));
        point_data.push(("contact_status".to_string(), 1, contact.status.clone()));
        point_data.push((
            "tangential_force".to_string(),
            1,
            contact.tangential.clone(),
        ));
        point_data.push((
            "tangential_force_vector".to_string(),
            3,
            contact.tangential_vector.clone(),
        ));
        point_data.push(("slip_vector".to_string(), 3, contact.slip_vector.clone()));
    }
    let mut cell_data = vec![(
        "subdomain".to_string(),
        1,
        b.parts.iter().map(|&p| p as f64).collect(),
    )];
    if request.wants("stress") && !fields.stress.is_empty() {
        cell_data.push((
            "stress".to_string(),
            6,
            fields
                .stress
                .iter()
                .flat_map(|s| s.iter().copied())
                .collect(),
        ));
        cell_data.push(("von_mises".to_string(), 1, fields.von_mises.clone()));
    }
    VtuPiece {
        dim,
        coords: &b.coords,
        cells: &b.cells,
        point_data,
        cell_data,
        node_ids: None,
    }
}
