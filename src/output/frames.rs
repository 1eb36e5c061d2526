//! Frames of a run for ParaView, and progress on stderr.
//!
//! Every `every` steps (and at the last, and in ADR at the end of every load increment) a frame
//! is written: `frame_NNNNNN.vtm`, a multiblock whose blocks are named after the bodies, and
//! its datasets in the folder `frame_NNNNNN/`: per deformable body `<body>/particles` (one
//! vertex per particle) and `<body>/surface` (its master segments on their own nodes, with
//! the particles' point data), per rigid body `<body>` (its faces). Points are reference
//! positions and `displacement` moves them to the deformed ones (ParaView's Warp By Vector at
//! scale 1). One `run.pvd` lists the frames as a time series: explicit runs at their time (s),
//! ADR runs at the load factor (see [`FrameWriter`]). The `.pvd` is rewritten after each
//! frame, so an interrupted run still leaves a collection ParaView opens. With the first frame,
//! `view.py` is written beside it: a pvpython script showing the last frame, the slaves'
//! surfaces coloured by `contact_pressure`, the masters translucent, the camera on the contact.
//!
//! In a run decomposed over MPI ranks each rank writes its own particles,
//! `<body>_particles_<rank>.vtu`, and the first rank the rest: the `.vtm`, whose `particles`
//! block is then a multi-piece block of those files (VTK's `vtkMultiPieceDataSet`, one block
//! in ParaView), a `<body>_particles.pvtu` beside them that opens the particles alone, the
//! surface (its nodes' values sent by their owners), the rigid bodies and the `.pvd`. Put
//! together in rank order, the pieces are the one-process frame.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::body::stress::{von_mises, Tensor};
use crate::body::Body;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::output::analysis::{normal_forces, surface_loads};
use std::io::{IsTerminal, Write};

use crate::output::vtk::{
    write_atomically, write_pvtu, write_vtm, write_vtu_with_field_data, BlockNode, CellSpec, Field,
    PvdCollection,
};
use crate::solver::Monitor;

/// Name of the collection file.
pub const PVD_NAME: &str = "run.pvd";

/// Name of the ParaView script written beside it.
pub const VIEW_NAME: &str = "view.py";

/// The script, before the run's bodies are filled in.
const VIEW_TEMPLATE: &str = include_str!("view.py");

/// `view.py` for `model`: the template with its contact pairs and deformable bodies, and what
/// a quasi-static frame's step counts (`iteration_word`).
fn view_script(model: &Model, iteration_word: &str) -> String {
    let name = |k: usize| serde_json::to_string(model.bodies[k].name()).unwrap_or_default();
    let pairs: Vec<String> = model
        .contact_pairs()
        .into_iter()
        .map(|(s, m)| format!("({}, {})", name(s), name(m)))
        .collect();
    let deformable: Vec<String> = (0..model.bodies.len())
        .filter(|&k| model.bodies[k].as_pd().is_some())
        .map(name)
        .collect();
    // A body pressed on its own pre-cracks whose bonds cannot break: its damage is its cut's,
    // the faces the contact presses, which the picture shows by their pressure instead.
    let self_pressed: Vec<usize> = model
        .contact_pairs()
        .into_iter()
        .filter(|(s, m)| s == m)
        .map(|(s, _)| s)
        .collect();
    let damage: Vec<String> = (0..model.bodies.len())
        .filter(|&k| {
            model.bodies[k]
                .as_pd()
                .is_some_and(|pd| pd.may_break() || !self_pressed.contains(&k))
        })
        .map(name)
        .collect();
    VIEW_TEMPLATE
        .replacen("PAIRS = []", &format!("PAIRS = [{}]", pairs.join(", ")), 1)
        .replacen(
            "DEFORMABLE = []",
            &format!("DEFORMABLE = [{}]", deformable.join(", ")),
            1,
        )
        .replacen(
            "DAMAGE = []",
            &format!("DAMAGE = [{}]", damage.join(", ")),
            1,
        )
        .replacen(
            "ITERATION = \"ADR iteration\"",
            &format!("ITERATION = \"{iteration_word}\""),
            1,
        )
}

/// Six or more digits.
fn is_step(d: &str) -> bool {
    d.len() >= 6 && d.bytes().all(|b| b.is_ascii_digit())
}

/// A frame file or folder this writer makes (`frame_NNNNNN.vtm`, `frame_NNNNNN/`), or one of
/// the flat frames earlier versions wrote (`particles_NNNNNN.vtu`, `segments_NNNNNN.vtu`).
fn is_frame_name(name: &str) -> bool {
    if let Some(d) = name.strip_prefix("frame_") {
        return is_step(d.strip_suffix(".vtm").unwrap_or(d));
    }
    let Some(stem) = name.strip_suffix(".vtu") else {
        return false;
    };
    let digits = stem
        .strip_prefix("particles_")
        .or_else(|| stem.strip_prefix("segments_"));
    digits.is_some_and(is_step)
}

/// A body name as a file name: letters, digits, `-`, `_` and `.` kept, the rest `_`.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with('.') {
        format!("body{s}")
    } else {
        s
    }
}

/// One frame listed in the `.pvd`.
#[derive(Clone, Debug)]
struct Entry {
    step: usize,
    time: f64,
    file: String,
    /// ADR: the load factor before this frame's increment, the increment's own, the increment's
    /// first iteration (the last of the one before) and, once it is over, its last iteration.
    lo: f64,
    hi: f64,
    start: usize,
    end: Option<usize>,
}

/// Writes the frames of a run.
///
/// ADR has no time: a frame's `.pvd` timestep is the load factor, interpolated by iteration
/// within a load increment. Increment `k` of `K` applies the load factor `k/K`; a frame at
/// iteration `i` of an increment that began after iteration `s` and ended at iteration `e` is
/// at `(k−1)/K + (i−s)/(e−s)/K`, so the equilibrium that ends increment `k` is at `k/K`
/// exactly, and with one increment (the default: the full load at once) the timestep is the
/// relaxation's progress `i/e`. Until an increment is over, `e` is its latest frame.
pub struct FrameWriter {
    folder: PathBuf,
    every: usize,
    /// ADR (pseudo-time = load factor) or explicit (time in s).
    pub(crate) adr: bool,
    /// What a quasi-static frame's step counts, for `view.py`'s caption: "ADR iteration", or
    /// "Newton iteration" for the static solver.
    pub iteration_word: &'static str,
    entries: Vec<Entry>,
    lo: f64,
    hi: f64,
    start: usize,
    last_written: Option<usize>,
    /// ADR: an increment was cut back, and the state it starts again from is a frame already.
    restarted: bool,
}

impl FrameWriter {
    /// A writer into `folder` (created if missing). Frames of an earlier run in the folder
    /// (`frame_NNNNNN.vtm` and `frame_NNNNNN/`, and the flat `particles_NNNNNN.vtu`,
    /// `segments_NNNNNN.vtu` of earlier versions) are removed, so that the folder never mixes
    /// two runs; other files are left alone.
    pub fn new(folder: &Path, every: usize) -> Result<FrameWriter> {
        std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
        let entries = std::fs::read_dir(folder).map_err(|e| Error::output(folder, e))?;
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            if is_frame_name(name) {
                let path = entry.path();
                let removed = if path.is_dir() {
                    std::fs::remove_dir_all(&path)
                } else {
                    std::fs::remove_file(&path)
                };
                removed.map_err(|e| Error::output(&path, e))?;
            }
        }
        Ok(FrameWriter::for_pieces(folder, every))
    }

    /// The writer of a decomposed run's other ranks: each writes its particles' piece of
    /// every frame into the folder the first rank's [`new`](Self::new) prepared, and
    /// sends the first rank its surface nodes' values.
    pub fn for_pieces(folder: &Path, every: usize) -> FrameWriter {
        FrameWriter {
            folder: folder.to_path_buf(),
            every: every.max(1),
            adr: false,
            iteration_word: "ADR iteration",
            entries: Vec::new(),
            lo: 0.0,
            hi: 1.0,
            start: 0,
            last_written: None,
            restarted: false,
        }
    }

    /// Path of the `.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.folder.join(PVD_NAME)
    }

    /// Path of the last frame written (its `.vtm`).
    pub fn last_frame(&self) -> Option<PathBuf> {
        self.last_written
            .map(|s| self.folder.join(format!("frame_{s:06}.vtm")))
    }

    /// ADR: a load increment applying `factor` of the load begins after `iteration`; the state
    /// the increment before ended in is written as a frame first.
    pub fn load_increment(&mut self, model: &Model, factor: f64, iteration: usize) -> Result<()> {
        if iteration > 0 && !std::mem::take(&mut self.restarted) {
            self.write(model, iteration, iteration as f64)?;
        }
        for e in &mut self.entries {
            e.end.get_or_insert(iteration);
        }
        self.lo = if iteration > 0 { self.hi } else { 0.0 };
        self.hi = factor;
        self.start = iteration;
        Ok(())
    }

    /// ADR: the increment that began after iteration `start` lost a slave in its transient and
    /// starts again from the equilibrium at load factor `done` with a shorter step. Its
    /// frames, states off the load path, are removed (the folder and the `.pvd`); the state it
    /// starts again from was written when the increment began.
    pub fn cut_back(&mut self, done: f64) -> Result<()> {
        let start = self.start;
        let (kept, dropped): (Vec<Entry>, Vec<Entry>) = std::mem::take(&mut self.entries)
            .into_iter()
            .partition(|e| e.step <= start);
        self.entries = kept;
        for e in &dropped {
            let vtm = self.folder.join(&e.file);
            let dir = vtm.with_extension("");
            std::fs::remove_dir_all(&dir).map_err(|err| Error::output(&dir, err))?;
            std::fs::remove_file(&vtm).map_err(|err| Error::output(&vtm, err))?;
        }
        self.hi = done;
        self.restarted = true;
        if !dropped.is_empty() {
            self.last_written = self.entries.last().map(|e| e.step);
            let mut pvd = PvdCollection::default();
            for e in &self.entries {
                pvd.push(self.timestep(e), e.file.clone());
            }
            pvd.write(&self.pvd_path())?;
        }
        Ok(())
    }

    /// The `.pvd` timestep of an entry.
    fn timestep(&self, e: &Entry) -> f64 {
        if !self.adr {
            return e.time;
        }
        let end = e.end.or(self.last_written).unwrap_or(e.step);
        if end > e.start {
            e.lo + (e.hi - e.lo) * (e.step - e.start) as f64 / (end - e.start) as f64
        } else {
            e.hi
        }
    }

    /// Writes the frame of `step` at time `t` (ADR: `t` is the iteration).
    pub fn write(&mut self, model: &Model, step: usize, t: f64) -> Result<()> {
        if self.last_written == Some(step) {
            return Ok(());
        }
        let dir_name = format!("frame_{step:06}");
        let dir = self.folder.join(&dir_name);
        std::fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
        let field_data: Vec<(&str, f64)> = if self.adr {
            vec![("load_factor", self.hi), ("iteration", step as f64)]
        } else {
            vec![("time", t), ("step", step as f64)]
        };
        let rank = model.rank();
        let root = rank == 0;
        // A decomposed run: every rank writes its own particles (a piece).
        let ranks = model
            .domain
            .as_ref()
            .map(|d| d.comm().size())
            .filter(|&r| r > 1);
        let mut blocks = Vec::new();
        let mut stems: Vec<String> = Vec::new();
        for (k, b) in model.bodies.iter().enumerate() {
            let mut stem = file_stem(b.name());
            if stems.contains(&stem) {
                stem = format!("{stem}_{k}");
            }
            stems.push(stem.clone());
            match b {
                Body::Deformable(pd) => {
                    let n = pd.len();
                    let reference = &pd.case.particles.position;
                    // The contact pressure, recovered over the surface, needs the contact forces
                    // of every boundary particle (in a decomposed run, sent by their owners).
                    let forces = match &model.domain {
                        Some(d) => {
                            let boundary: Vec<usize> = (0..n)
                                .filter(|&i| pd.case.segments.pressure_area[i] > 0.0)
                                .collect();
                            let got =
                                d.collect(k, &boundary, 1, |i, out| out.push(pd.pressure_force(i)));
                            let mut f = vec![0.0; n];
                            for (&i, v) in boundary.iter().zip(got) {
                                f[i] = v;
                            }
                            f
                        }
                        None => normal_forces(pd),
                    };
                    let (pressure, own_pressure) = surface_loads(pd, &forces, |s| {
                        (s.recovered_pressure(), s.particle_pressure())
                    });
                    // This process's particles (all of them in one process).
                    let own = model
                        .domain
                        .as_ref()
                        .map_or(0..n, |d| d.ranges[k][rank].clone());
                    let at: Vec<usize> = own.clone().collect();
                    // The stress of this process's particles, from their neighbourhoods (in a
                    // decomposed run, the ghosts' displacements fresh from their owners).
                    let stress = match &model.domain {
                        Some(d) => pd.stress(&d.displacements(k, &pd.u), &at, Some(&pressure)),
                        None => pd.stress(&pd.u, &at, Some(&pressure)),
                    };
                    // The particle's own state, where it is held.
                    let first = own.start;
                    let here = |i: usize| {
                        (
                            [pd.u[i], pd.v[i], pd.force[i], pd.contact_force[i]],
                            [pressure[i], own_pressure[i]],
                            stress[i - first],
                        )
                    };
                    let fields = point_fields(model, k, &at, |m| here(at[m]));
                    // The pieces' arrays, for the `.pvtu` (the fields move into the piece).
                    let arrays: Vec<(String, &str, usize)> =
                        fields.iter().map(Field::layout).collect();
                    let pfile = match ranks {
                        Some(_) => format!("{dir_name}/{stem}_particles_{rank}.vtu"),
                        None => format!("{dir_name}/{stem}_particles.vtu"),
                    };
                    write_vtu_with_field_data(
                        &self.folder.join(&pfile),
                        &reference[own],
                        CellSpec::Vertices,
                        fields,
                        vec![],
                        &field_data,
                    )?;
                    // The surface: the master segments on their own nodes, numbered in order
                    // of first use, with the particles' values there (in a decomposed run,
                    // sent by their owners: this also waits for every rank's piece).
                    let mut local = vec![u32::MAX; n];
                    let mut nodes: Vec<usize> = Vec::new();
                    let quads: Vec<[u32; 4]> = pd
                        .segments()
                        .iter()
                        .map(|s| {
                            s.nodes.map(|i| {
                                let i = i as usize;
                                if local[i] == u32::MAX {
                                    local[i] = nodes.len() as u32;
                                    nodes.push(i);
                                }
                                local[i]
                            })
                        })
                        .collect();
                    let surface_fields = match &model.domain {
                        Some(d) => {
                            let got = d.collect(k, &nodes, WIDTH, |i, out| {
                                let (v, p, t) = here(i);
                                out.extend(v.iter().flat_map(|v| v.iter()));
                                out.extend(p);
                                out.extend(t.iter());
                            });
                            point_fields(model, k, &nodes, |m| {
                                let r = &got[WIDTH * m..WIDTH * (m + 1)];
                                let v3 = |c: usize| Vec3::new(r[3 * c], r[3 * c + 1], r[3 * c + 2]);
                                (
                                    [v3(0), v3(1), v3(2), v3(3)],
                                    [r[12], r[13]],
                                    Tensor::from_column_slice(&r[14..]),
                                )
                            })
                        }
                        None => point_fields(model, k, &nodes, |m| here(nodes[m])),
                    };
                    if !root {
                        continue;
                    }
                    let sfile = format!("{dir_name}/{stem}_surface.vtu");
                    let surface_points: Vec<Vec3> = nodes.iter().map(|&i| reference[i]).collect();
                    let cells = quads.len();
                    write_vtu_with_field_data(
                        &self.folder.join(&sfile),
                        &surface_points,
                        CellSpec::Quads(quads),
                        surface_fields,
                        vec![Field::int("body", vec![k as i32; cells])],
                        &field_data,
                    )?;
                    // A decomposed run's particles: one piece per rank, a multi-piece block
                    // of the frame, and a `.pvtu` (VTK's parallel unstructured grid) beside
                    // them for those who open the particles alone.
                    let particles = match ranks {
                        Some(r) => {
                            let pieces: Vec<String> = (0..r)
                                .map(|q| format!("{stem}_particles_{q}.vtu"))
                                .collect();
                            let pvtu = self
                                .folder
                                .join(format!("{dir_name}/{stem}_particles.pvtu"));
                            write_pvtu(&pvtu, &pieces, &arrays)?;
                            BlockNode::Pieces(
                                "particles".into(),
                                pieces.iter().map(|p| format!("{dir_name}/{p}")).collect(),
                            )
                        }
                        None => BlockNode::DataSet("particles".into(), pfile),
                    };
                    blocks.push(BlockNode::Block(
                        b.name().to_string(),
                        vec![particles, BlockNode::DataSet("surface".into(), sfile)],
                    ));
                }
                Body::Rigid(_) if !root => {}
                Body::Rigid(rb) => {
                    let file = format!("{dir_name}/{stem}.vtu");
                    let quads: Vec<[u32; 4]> = rb.faces.iter().map(|f| f.nodes).collect();
                    let cells = quads.len();
                    write_vtu_with_field_data(
                        &self.folder.join(&file),
                        &rb.vertices,
                        CellSpec::Quads(quads),
                        vec![Field::vector(
                            "displacement",
                            vec![rb.translation; rb.vertices.len()],
                        )],
                        vec![Field::int("body", vec![k as i32; cells])],
                        &field_data,
                    )?;
                    blocks.push(BlockNode::DataSet(b.name().to_string(), file));
                }
            }
        }
        if !root {
            self.last_written = Some(step);
            return Ok(());
        }
        if self.entries.is_empty() {
            let view = self.folder.join(VIEW_NAME);
            let script = view_script(model, self.iteration_word);
            write_atomically(&view, |w| w.write_all(script.as_bytes()))?;
        }
        let vtm = format!("{dir_name}.vtm");
        write_vtm(&self.folder.join(&vtm), &blocks)?;
        self.entries.push(Entry {
            step,
            time: t,
            file: vtm,
            lo: self.lo,
            hi: self.hi,
            start: self.start,
            end: None,
        });
        self.last_written = Some(step);
        let mut pvd = PvdCollection::default();
        for e in &self.entries {
            pvd.push(self.timestep(e), e.file.clone());
        }
        pvd.write(&self.pvd_path())
    }
}

/// A particle's state in a frame: `u`, `v`, force, contact force; the recovered and the
/// particle's own contact pressure; its stress.
type PointState = ([Vec3; 4], [f64; 2], Tensor);

/// Numbers of a [`PointState`] sent between ranks.
const WIDTH: usize = 4 * 3 + 2 + 9;

/// The point fields of body `k` at its particles `at`: the state of `at[m]` from
/// `state(m)`, the rest from the case.
fn point_fields(
    model: &Model,
    k: usize,
    at: &[usize],
    state: impl Fn(usize) -> PointState,
) -> Vec<Field> {
    let pd = model.bodies[k].as_pd().expect("a deformable body");
    let states: Vec<PointState> = (0..at.len()).map(state).collect();
    let column = |c: usize| states.iter().map(|s| s.0[c]).collect::<Vec<Vec3>>();
    let case = &pd.case;
    let opened_surface = pd.new_surface();
    let opened = |i: usize| opened_surface.as_ref().is_some_and(|s| s.is_new[i]);
    let mut fields = vec![
        Field::vector("displacement", column(0)),
        Field::vector("velocity", column(1)),
        Field::vector("force", column(2)),
        Field::vector("contact_force", column(3)),
        Field::scalar("contact_pressure", states.iter().map(|s| s.1[0]).collect()),
        Field::scalar("particle_pressure", states.iter().map(|s| s.1[1]).collect()),
        Field::tensor("stress", states.iter().map(|s| s.2).collect()),
        Field::scalar(
            "von_mises",
            states.iter().map(|s| von_mises(&s.2)).collect(),
        ),
        // The surface as built and what broken bonds opened since ([`crate::body::new_surface`]).
        Field::int(
            "surface",
            at.iter()
                .map(|&i| (case.surface.is_surface[i] || opened(i)) as i32)
                .collect(),
        ),
        // Where the body is pressed on the faces found again, a crack's edge on the outer
        // surface faces between the two faces, as the contact reads it.
        Field::vector(
            "normal",
            at.iter()
                .map(|&i| match &opened_surface {
                    Some(s) if s.is_new[i] => s.normal[i],
                    _ => pd.surface_normals()[i],
                })
                .collect(),
        ),
        // The mesh's own boundary nodes, beside the eigenvalue surface.
        Field::int(
            "boundary_node",
            at.iter()
                .map(|&i| case.segments.boundary_node[i] as i32)
                .collect(),
        ),
        Field::int("body", vec![k as i32; at.len()]),
        Field::scalar(
            "volume",
            at.iter().map(|&i| case.particles.volume[i]).collect(),
        ),
    ];
    // Where bonds may break: the share of each particle's family volume it has lost, the
    // surface the broken bonds opened, and the piece each particle is in (0 the largest).
    if let Some(f) = &pd.fracture {
        fields.push(Field::scalar(
            "damage",
            at.iter().map(|&i| pd.damage(i)).collect(),
        ));
        fields.push(Field::int(
            "new_surface",
            at.iter().map(|&i| opened(i) as i32).collect(),
        ));
        let (fragment, _) = f.fragment_labels(&case.bonds);
        fields.push(Field::int(
            "fragment",
            at.iter().map(|&i| fragment[i] as i32).collect(),
        ));
    }
    // Where the body is in a pair with friction: the shear traction (friction's force over
    // the particle's pressure area, as `particle_pressure` takes the normal one) and whether
    // it sticks (1), slips (0) or touches nothing as a slave (−1).
    if let Some(f) = &pd.friction {
        fields.push(Field::vector(
            "friction_traction",
            at.iter()
                .map(|&i| {
                    let area = case.segments.pressure_area[i];
                    if area > 0.0 {
                        pd.friction_force(i) / area
                    } else {
                        Vec3::zeros()
                    }
                })
                .collect(),
        ));
        fields.push(Field::int(
            "stick",
            at.iter().map(|&i| i32::from(f.stick[i])).collect(),
        ));
    }
    fields
}

/// Progress bar + frames: the monitor of `run` and `demo`.
pub struct RunMonitor {
    pub frames: Option<FrameWriter>,
    bar: ProgressBar,
    label: &'static str,
    stop: Arc<AtomicBool>,
    /// The last step reported: number, (pseudo-)time and measure (residual or energy drift),
    /// so that a run that fails can still say how far it got.
    pub last_step: (usize, f64, f64),
    /// Where stderr is not a terminal (a log file, a batch job, a pipe) the bar draws nothing:
    /// a plain line every [`plain_progress_every`] instead, from the run's start, the last
    /// line's time and the interval.
    plain: Option<(Instant, Instant, Duration)>,
    /// The static solver's conjugate-gradient iterations so far: its steps are Newton
    /// iterations, each shown ([`Monitor::linear_iterations`]).
    linear: Option<usize>,
    /// ADR relaxing where the static solver's Newton iterations stalled.
    relaxing: bool,
}

/// How often a run whose stderr is not a terminal prints a progress line: every 5 s, or every
/// `PDCONTACT_PROGRESS_SECONDS` (a batch system's log may want fewer lines).
pub fn plain_progress_every() -> Duration {
    std::env::var("PDCONTACT_PROGRESS_SECONDS")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0)
        .map_or(Duration::from_secs(5), Duration::from_secs_f64)
}

impl RunMonitor {
    /// A monitor; `quiet` hides the progress bar; `stop` is raised by Ctrl-C.
    pub fn new(
        frames: Option<FrameWriter>,
        quiet: bool,
        adr: bool,
        stop: Arc<AtomicBool>,
    ) -> RunMonitor {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(4));
            b.set_style(
                ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            b
        };
        let frames = frames.map(|mut f| {
            f.adr = adr;
            f
        });
        let plain = (!quiet && !std::io::stderr().is_terminal()).then(|| {
            let now = Instant::now();
            (now, now, plain_progress_every())
        });
        RunMonitor {
            frames,
            bar,
            label: if adr { "residual" } else { "energy drift" },
            stop,
            last_step: (0, 0.0, 0.0),
            plain,
            linear: None,
            relaxing: false,
        }
    }
}

impl Monitor for RunMonitor {
    fn step(&mut self, model: &Model, step: usize, time: f64, measure: f64) -> Result<()> {
        self.last_step = (step, time, measure);
        // A Newton iteration costs what tens of ADR iterations do: each is shown.
        let newton = self.linear.is_some() && !self.relaxing;
        let word = if newton {
            "Newton iteration"
        } else if self.relaxing {
            "ADR step (Newton stalled)"
        } else {
            "step"
        };
        let linear = |sep: &str| {
            self.linear
                .map_or(String::new(), |n| format!("{sep}linear iterations {n}"))
        };
        if newton || step.is_multiple_of(50) {
            self.bar.set_message(format!(
                "{word} {step}  {} {measure:.3e}{}  contacts {}  Verlet rebuilds {}",
                self.label,
                linear("  "),
                model.contact_count(),
                model.verlet_rebuilds()
            ));
            self.bar.tick();
        }
        if let Some((start, last, every)) = &mut self.plain {
            if last.elapsed() >= *every {
                *last = Instant::now();
                eprintln!(
                    "{:.0} s: {word} {step}, {} {measure:.3e}{}, contacts {}",
                    start.elapsed().as_secs_f64(),
                    self.label,
                    linear(", "),
                    model.contact_count()
                );
            }
        }
        if let Some(f) = &mut self.frames {
            if step.is_multiple_of(f.every) {
                f.write(model, step, time)?;
            }
        }
        Ok(())
    }

    fn load_increment(&mut self, model: &Model, factor: f64, iteration: usize) -> Result<()> {
        match &mut self.frames {
            Some(f) => f.load_increment(model, factor, iteration),
            None => Ok(()),
        }
    }

    fn cut_back(&mut self, _model: &Model, done: f64, target: f64, iteration: usize) -> Result<()> {
        let line = format!(
            "a slave went through its master at iteration {iteration}: the increment starts again from load factor {done:.4} with half the step, to {target:.4}"
        );
        if self.plain.is_some() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
        match &mut self.frames {
            Some(f) => f.cut_back(done),
            None => Ok(()),
        }
    }

    fn linear_iterations(&mut self, total: usize) {
        self.linear = Some(total);
    }

    fn relaxation(&mut self, on: bool) {
        self.relaxing = on;
    }

    fn finish(&mut self, model: &Model, step: usize, time: f64) -> Result<()> {
        self.bar.finish_and_clear();
        if let Some(f) = &mut self.frames {
            f.write(model, step, time)?;
        }
        Ok(())
    }

    fn interrupted(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::is_frame_name;

    #[test]
    fn only_frame_files_are_recognised() {
        assert!(is_frame_name("particles_000120.vtu"));
        assert!(is_frame_name("segments_1234567.vtu"));
        assert!(!is_frame_name("particles_12.vtu"));
        assert!(!is_frame_name("particles_00012a.vtu"));
        assert!(!is_frame_name("my_particles_000120.vtu"));
        assert!(!is_frame_name("particles_000120.vtu.bak"));
        assert!(!is_frame_name("run.pvd"));
        assert!(is_frame_name("frame_000120.vtm"));
        assert!(is_frame_name("frame_000120"));
        assert!(!is_frame_name("frame_12.vtm"));
        assert!(!is_frame_name("frame_000120.vtu"));
    }
}
