//! Trajectories for molecular viewers (SPEC §8): PDB (+CONECT), PSF and
//! DCD, read by mdtraj, VMD, PyMOL, MDAnalysis and nglview.
//!
//! [`Topology::from_world`]: one bead per sample (Gauss) point of every rod,
//! one chain per rod, bonds between consecutive beads of a rod (and
//! last–first on closed rods), residues named `SKB`. [`Topology::new`]: any
//! chains with residue names of their own (e.g. one bead per nucleotide,
//! `DA`…`DT`) and links across chains (hydrogen bonds). Beads are
//! phosphorus (element P, mass 30.97) so readers guess no odd element, in
//! HETATM records, whose CONECT bonds mdtraj keeps whatever the residue
//! name (python/tests/test_dna_trajectory.py loads them). Coordinates are written
//! in Å: `scale` is the number of Å per length unit of the world (10 for nm,
//! 1e10 for m — PDB's 8.3 columns then overflow quickly; use PSF + DCD).
//!
//! Every file is written so that an interrupted run never leaves a corrupt
//! one: PDB and PSF go through a temporary file + rename; the DCD writer
//! appends a complete frame before it updates the frame count in the header,
//! and readers that count frames from the file size (VMD's plugin, which
//! mdtraj uses) ignore a partial trailing frame; reopening for append
//! truncates it.
use crate::error::{Error, Result};
use crate::world::World;
use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Residue name of a bead that has none given (not a standard residue).
pub const RESIDUE_NAME: &str = "SKB";
/// Element, atom name and type of every bead.
pub const BEAD_ELEMENT: &str = "P";
/// Mass of a bead (u): phosphorus.
pub const BEAD_MASS: f64 = 30.97;

/// One chain: its bead count, whether it is closed, and its beads'
/// residue names (empty: every bead is [`RESIDUE_NAME`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chain {
    pub beads: usize,
    pub closed: bool,
    pub residues: Vec<String>,
}

/// Chains of beads plus bonds between any two beads (`links`, e.g. the
/// hydrogen bonds of a duplex), in bead indices over all chains.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    pub chains: Vec<Chain>,
    pub links: Vec<[usize; 2]>,
}

impl Topology {
    /// One chain per rod (world order), one bead per sample point.
    pub fn from_world(world: &World) -> Topology {
        let chains = world
            .rods()
            .map(|(_, r)| Chain {
                beads: r.sample_params().len(),
                closed: r.knots().kind() == crate::spline::KnotKind::Periodic,
                residues: Vec::new(),
            })
            .collect();
        Topology { chains, links: Vec::new() }
    }
    /// A checked topology of given chains and links: residue names of 1–3
    /// letters or digits (one per bead or none), links between two distinct
    /// existing beads.
    pub fn new(chains: Vec<Chain>, links: Vec<[usize; 2]>) -> Result<Topology> {
        let n: usize = chains.iter().map(|c| c.beads).sum();
        for (i, c) in chains.iter().enumerate() {
            if !c.residues.is_empty() && c.residues.len() != c.beads {
                return Err(Error::input(format!(
                    "chain {i}: {} residue names for {} beads",
                    c.residues.len(),
                    c.beads
                )));
            }
            // PDB's resName is three columns.
            let bad = |r: &&String| r.is_empty() || r.len() > 3 || !r.bytes().all(|b| b.is_ascii_alphanumeric());
            if let Some(r) = c.residues.iter().find(bad) {
                return Err(Error::input(format!("chain {i}: residue name {r:?} is not 1–3 letters or digits")));
            }
        }
        if let Some([a, b]) = links.iter().find(|[a, b]| a == b || *a >= n || *b >= n) {
            return Err(Error::input(format!("link {a}–{b}: beads must be two distinct of the {n} beads")));
        }
        let t = Topology { chains, links };
        let mut seen = std::collections::HashSet::new();
        if let Some([a, b]) = t.bonds().into_iter().find(|&[a, b]| !seen.insert((a.min(b), a.max(b)))) {
            return Err(Error::input(format!("link {a}–{b} is a bond already (along a chain or listed twice)")));
        }
        Ok(t)
    }
    pub fn n_beads(&self) -> usize {
        self.chains.iter().map(|c| c.beads).sum()
    }
    /// Bonds as 0-based bead index pairs: along each chain in chain order, then the links.
    pub fn bonds(&self) -> Vec<[usize; 2]> {
        let mut out = Vec::with_capacity(self.n_beads() + self.links.len());
        let mut start = 0;
        for c in &self.chains {
            out.extend((1..c.beads).map(|i| [start + i - 1, start + i]));
            if c.closed && c.beads > 2 {
                out.push([start + c.beads - 1, start]);
            }
            start += c.beads;
        }
        out.extend_from_slice(&self.links);
        out
    }
    /// Chain of every bead.
    pub fn chain_of_bead(&self) -> Vec<usize> {
        self.chains.iter().enumerate().flat_map(|(i, c)| std::iter::repeat_n(i, c.beads)).collect()
    }
    /// Residue name of bead `k` of chain `c`.
    pub fn residue(&self, c: usize, k: usize) -> &str {
        self.chains[c].residues.get(k).map_or(RESIDUE_NAME, |r| r.as_str())
    }
}

/// Bead positions (length unit) of a world: sample points of every rod in world order.
pub fn bead_positions(world: &World) -> Vec<[f64; 3]> {
    world.rods().flat_map(|(_, r)| r.sample_points().into_iter().map(|p| [p.x, p.y, p.z])).collect()
}

fn check_frame(topo: &Topology, frame: &[[f64; 3]], scale: f64) -> Result<()> {
    if frame.len() != topo.n_beads() {
        return Err(Error::input(format!(
            "frame has {} beads but the topology has {} (did rods change since the topology was written?)",
            frame.len(),
            topo.n_beads()
        )));
    }
    crate::error::positive("length scale (Å per length unit)", scale)?;
    for (i, p) in frame.iter().enumerate() {
        for x in p {
            if !x.is_finite() {
                return Err(Error::input(format!("bead {i} has a non-finite coordinate ({x})")));
            }
        }
    }
    Ok(())
}

/// Chain identifier of chain `i` (A–Z, a–z, 0–9, repeating; each chain
/// also ends with TER so readers separate chains that share a letter).
fn chain_id(i: usize) -> char {
    const IDS: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    IDS[i % IDS.len()] as char
}

/// PDB text: one MODEL per frame (positions in length unit, times `scale`
/// → Å), then CONECT records for the bonds. Errors beyond 99,999 beads or
/// when a coordinate does not fit PDB's columns (−999.999 .. 9999.999 Å):
/// use PSF + DCD then.
pub fn pdb_string(topo: &Topology, frames: &[Vec<[f64; 3]>], scale: f64) -> Result<String> {
    pdb_string_marked(topo, frames, scale, None)
}

/// [`pdb_string`] with a B-factor per bead (the temperature-factor column,
/// by which VMD colours: e.g. broken base pairs), −99.99 … 999.99.
pub fn pdb_string_marked(
    topo: &Topology,
    frames: &[Vec<[f64; 3]>],
    scale: f64,
    bfactors: Option<&[f64]>,
) -> Result<String> {
    let n = topo.n_beads();
    if let Some(b) = bfactors {
        if b.len() != n {
            return Err(Error::input(format!("{} B-factors for {n} beads", b.len())));
        }
        if let Some((i, x)) = b.iter().enumerate().find(|(_, x)| !(**x > -99.995 && **x < 999.995)) {
            return Err(Error::input(format!("bead {i}: B-factor {x} does not fit PDB's column (-99.99 .. 999.99)")));
        }
    }
    if n > 99_999 {
        return Err(Error::input(format!("PDB holds at most 99,999 beads, got {n}: write PSF + DCD instead")));
    }
    if frames.is_empty() {
        return Err(Error::input("PDB: no frame to write"));
    }
    let chain = topo.chain_of_bead();
    let mut s = String::with_capacity(frames.len() * n * 81 + n * 32);
    s.push_str("REMARK   1 strandkit beads; coordinates in Angstrom\n");
    for (m, frame) in frames.iter().enumerate() {
        check_frame(topo, frame, scale)?;
        if frames.len() > 1 {
            let _ = writeln!(s, "MODEL     {:>4}", m + 1);
        }
        let mut first = 0;
        for (i, p) in frame.iter().enumerate() {
            let c = chain[i];
            if i > 0 && c != chain[i - 1] {
                s.push_str("TER\n");
                first = i;
            }
            let xyz = [p[0] * scale, p[1] * scale, p[2] * scale];
            if let Some(x) = xyz.iter().find(|x| !(**x > -999.9995 && **x < 9999.9995)) {
                return Err(Error::input(format!(
                    "bead {i} coordinate {x:.3} Å does not fit PDB columns (-999.999 .. 9999.999): lower the scale or write PSF + DCD"
                )));
            }
            let resid = (i - first + 1) % 10_000;
            let beta = bfactors.map_or(0.0, |b| b[i]);
            let _ = writeln!(
                s,
                // altLoc (column 17) blank.
                "HETATM{:>5} {:<4} {:>3} {}{:>4}    {:>8.3}{:>8.3}{:>8.3}{:>6.2}{:>6.2}          {:>2}  ",
                i + 1,
                format!(" {BEAD_ELEMENT}"),
                topo.residue(c, i - first),
                chain_id(c),
                resid,
                xyz[0],
                xyz[1],
                xyz[2],
                1.0,
                beta,
                BEAD_ELEMENT
            );
        }
        s.push_str("TER\n");
        if frames.len() > 1 {
            s.push_str("ENDMDL\n");
        }
    }
    // CONECT: every bead lists its bonded neighbours (both directions), ≤ 4 per record.
    let mut nbr = vec![Vec::new(); n];
    for [a, b] in topo.bonds() {
        nbr[a].push(b);
        nbr[b].push(a);
    }
    for (i, list) in nbr.iter().enumerate() {
        for part in list.chunks(4) {
            let _ = write!(s, "CONECT{:>5}", i + 1);
            for j in part {
                let _ = write!(s, "{:>5}", j + 1);
            }
            s.push('\n');
        }
    }
    s.push_str("END\n");
    Ok(s)
}

/// Writes [`pdb_string_marked`] atomically.
pub fn write_pdb(
    path: &Path,
    topo: &Topology,
    frames: &[Vec<[f64; 3]>],
    scale: f64,
    bfactors: Option<&[f64]>,
) -> Result<()> {
    super::write_atomic(path, pdb_string_marked(topo, frames, scale, bfactors)?.as_bytes())
}

/// Segment id of chain `i` (4 characters at most).
fn segid(i: usize) -> String {
    if i < 1000 {
        format!("R{i}")
    } else {
        format!("{i:X}")
    }
}

/// CHARMM PSF (fixed columns, as VMD's plugin reads them; mdtraj splits on
/// blanks): atoms with segment = rod, one residue per bead, bonds.
pub fn psf_string(topo: &Topology) -> Result<String> {
    let n = topo.n_beads();
    if n > 99_999_999 {
        return Err(Error::input(format!("PSF holds at most 99,999,999 beads, got {n}")));
    }
    if topo.chains.len() > 0xFFFF {
        return Err(Error::input(format!("PSF segment ids allow at most 65535 rods, got {}", topo.chains.len())));
    }
    let mut s = String::with_capacity(n * 72 + n * 20);
    s.push_str("PSF\n\n       1 !NTITLE\n REMARKS strandkit beads\n\n");
    let _ = writeln!(s, "{n:>8} !NATOM");
    let mut i = 0;
    for (c, ch) in topo.chains.iter().enumerate() {
        let seg = segid(c);
        for k in 0..ch.beads {
            i += 1;
            let _ = writeln!(
                s,
                "{:>8} {:<4} {:<4} {:<4} {:<4} {:<4} {:>14.6}{:>14.4}{:>8}",
                i,
                seg,
                (k + 1) % 10_000,
                topo.residue(c, k),
                BEAD_ELEMENT,
                BEAD_ELEMENT,
                0.0,
                BEAD_MASS,
                0
            );
        }
    }
    let bonds = topo.bonds();
    let _ = writeln!(s, "\n{:>8} !NBOND: bonds", bonds.len());
    for (k, [a, b]) in bonds.iter().enumerate() {
        let _ = write!(s, "{:>8}{:>8}", a + 1, b + 1);
        if k % 4 == 3 || k + 1 == bonds.len() {
            s.push('\n');
        }
    }
    s.push_str("\n       0 !NTHETA: angles\n\n\n       0 !NPHI: dihedrals\n\n\n       0 !NIMPHI: impropers\n\n\n");
    s.push_str("       0 !NDON: donors\n\n\n       0 !NACC: acceptors\n\n\n");
    Ok(s)
}

/// Writes [`psf_string`] atomically.
pub fn write_psf(path: &Path, topo: &Topology) -> Result<()> {
    super::write_atomic(path, psf_string(topo)?.as_bytes())
}

/// The header fields of a CHARMM DCD file (SPEC §8).
#[derive(Clone, Debug, PartialEq)]
pub struct DcdHeader {
    pub n_atoms: usize,
    /// Frames in the file (NSET).
    pub n_frames: usize,
    /// Step number of the first frame (ISTART) and steps between frames (NSAVC).
    pub istart: i32,
    pub nsavc: i32,
    /// Time step (DELTA; CHARMM uses AKMA units, we store the world's time unit).
    pub delta: f32,
    /// Two 80-character title lines.
    pub titles: [String; 2],
}

const HEADER_BYTES: u64 = 4 + 84 + 4 + 4 + 4 + 160 + 4 + 4 + 4 + 4;

fn frame_bytes(n: usize) -> u64 {
    (4 + 48 + 4) + 3 * (8 + 4 * n as u64)
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::io(path.display().to_string(), format!("{e}"))
}

fn title_bytes(t: &str) -> [u8; 80] {
    let mut b = [b' '; 80];
    for (o, c) in b.iter_mut().zip(t.bytes().filter(|c| c.is_ascii() && !c.is_ascii_control())) {
        *o = c;
    }
    b
}

fn header_bytes(h: &DcdHeader) -> Vec<u8> {
    let mut b = Vec::with_capacity(HEADER_BYTES as usize);
    let i32le = |b: &mut Vec<u8>, x: i32| b.extend_from_slice(&x.to_le_bytes());
    i32le(&mut b, 84);
    b.extend_from_slice(b"CORD");
    i32le(&mut b, h.n_frames as i32); // NSET
    i32le(&mut b, h.istart);
    i32le(&mut b, h.nsavc);
    i32le(&mut b, nstep(h)); // NSTEP
    for _ in 0..5 {
        i32le(&mut b, 0);
    }
    b.extend_from_slice(&h.delta.to_le_bytes());
    i32le(&mut b, 1); // unit-cell record present in every frame
    for _ in 0..8 {
        i32le(&mut b, 0);
    }
    i32le(&mut b, 24); // CHARMM version
    i32le(&mut b, 84);
    i32le(&mut b, 164);
    i32le(&mut b, 2);
    for t in &h.titles {
        b.extend_from_slice(&title_bytes(t));
    }
    i32le(&mut b, 164);
    i32le(&mut b, 4);
    i32le(&mut b, h.n_atoms as i32);
    i32le(&mut b, 4);
    debug_assert_eq!(b.len() as u64, HEADER_BYTES);
    b
}

/// NSTEP: the step number of the last frame.
fn nstep(h: &DcdHeader) -> i32 {
    h.istart.saturating_add((h.n_frames as i32 - 1).max(0).saturating_mul(h.nsavc))
}

/// Appends frames to a CHARMM DCD file (our own writer; layout in SPEC §8).
pub struct DcdWriter {
    file: File,
    path: PathBuf,
    header: DcdHeader,
    buf: Vec<u8>,
}

impl DcdWriter {
    /// Creates (or replaces) `path` with a header and no frame. The header
    /// goes through a temporary file + rename, so a crash here leaves
    /// either the old file or a valid empty trajectory.
    pub fn create(path: &Path, header: DcdHeader) -> Result<DcdWriter> {
        if header.n_atoms == 0 || header.n_atoms > (i32::MAX as usize - 4) / 4 {
            return Err(Error::input(format!("DCD atom count must be in 1..=536870910, got {}", header.n_atoms)));
        }
        if header.nsavc < 1 {
            return Err(Error::input(format!("DCD nsavc (steps between frames) must be >= 1, got {}", header.nsavc)));
        }
        crate::error::finite("DCD delta", header.delta as f64)?;
        let header = DcdHeader { n_frames: 0, ..header };
        super::write_atomic(path, &header_bytes(&header))?;
        let file = OpenOptions::new().read(true).write(true).open(path).map_err(io_err(path))?;
        Ok(DcdWriter { file, path: path.to_path_buf(), header, buf: Vec::new() })
    }

    /// Reopens an existing DCD to append frames. A partial trailing frame
    /// (interrupted run) is cut off and the frame count set from the file size.
    pub fn open_append(path: &Path) -> Result<DcdWriter> {
        let mut file = OpenOptions::new().read(true).write(true).open(path).map_err(io_err(path))?;
        let mut head = vec![0u8; HEADER_BYTES as usize];
        file.read_exact(&mut head).map_err(|e| Error::io(path.display().to_string(), format!("not a DCD file ({e})")))?;
        let mut header = parse_header(path, &head)?;
        let size = file.metadata().map_err(io_err(path))?.len();
        let complete = (size - HEADER_BYTES) / frame_bytes(header.n_atoms);
        header.n_frames = complete as usize;
        file.set_len(HEADER_BYTES + complete * frame_bytes(header.n_atoms)).map_err(io_err(path))?;
        let mut w = DcdWriter { file, path: path.to_path_buf(), header, buf: Vec::new() };
        w.write_counts()?;
        Ok(w)
    }

    pub fn header(&self) -> &DcdHeader {
        &self.header
    }
    pub fn n_frames(&self) -> usize {
        self.header.n_frames
    }

    /// Appends one frame: positions (length unit) × `scale` → Å, stored as
    /// float32, with a zero (non-periodic) unit cell. A position that is
    /// not finite or whose Å value exceeds float32 (±3.4e38) is an error
    /// and nothing is written.
    pub fn write_frame(&mut self, positions: &[[f64; 3]], scale: f64) -> Result<()> {
        let n = self.header.n_atoms;
        if positions.len() != n {
            return Err(Error::input(format!(
                "DCD frame has {} atoms but the file has {n} (did rods change?)",
                positions.len()
            )));
        }
        crate::error::positive("length scale (Å per length unit)", scale)?;
        if let Some(i) = positions.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(Error::input(format!("atom {i} has a non-finite coordinate {:?}", positions[i])));
        }
        // Stored as float32: a finite value beyond ±f32::MAX would land on
        // disk as inf. Checked before anything is written.
        for (i, p) in positions.iter().enumerate() {
            if let Some(x) = p.iter().map(|x| x * scale).find(|x| !(*x as f32).is_finite()) {
                return Err(Error::invalid(
                    format!("DCD atom {i} coordinate (Å, float32)"),
                    format!("{x:e}"),
                    format!("within ±{:e} (lower the scale)", f32::MAX),
                ));
            }
        }
        let b = &mut self.buf;
        b.clear();
        b.extend_from_slice(&48i32.to_le_bytes());
        // CHARMM cell order A, γ, B, β, α, C: zero lengths, right angles.
        for x in [0.0f64, 90.0, 0.0, 90.0, 90.0, 0.0] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&48i32.to_le_bytes());
        let len = (4 * n) as i32;
        for a in 0..3 {
            b.extend_from_slice(&len.to_le_bytes());
            for p in positions {
                b.extend_from_slice(&((p[a] * scale) as f32).to_le_bytes());
            }
            b.extend_from_slice(&len.to_le_bytes());
        }
        let end = HEADER_BYTES + self.header.n_frames as u64 * frame_bytes(n);
        {
            let io = io_err(&self.path);
            self.file.seek(SeekFrom::Start(end)).map_err(&io)?;
            self.file.write_all(&self.buf).map_err(&io)?;
        }
        // Only a complete frame is counted.
        self.header.n_frames += 1;
        self.write_counts()
    }

    /// NSET and NSTEP in the header.
    fn write_counts(&mut self) -> Result<()> {
        let io = io_err(&self.path);
        self.file.seek(SeekFrom::Start(8)).map_err(&io)?;
        self.file.write_all(&(self.header.n_frames as i32).to_le_bytes()).map_err(&io)?;
        self.file.seek(SeekFrom::Start(20)).map_err(&io)?;
        self.file.write_all(&nstep(&self.header).to_le_bytes()).map_err(&io)
    }

    /// Pushes everything to disk (fsync), e.g. before a long pause.
    pub fn flush(&mut self) -> Result<()> {
        self.file.sync_all().map_err(io_err(&self.path))
    }

    /// Flushes and closes.
    pub fn close(mut self) -> Result<()> {
        self.flush()
    }
}

fn parse_header(path: &Path, b: &[u8]) -> Result<DcdHeader> {
    let bad = |what: &str| Error::io(path.display().to_string(), format!("not a CHARMM DCD file written by strandkit ({what})"));
    let i32at = |o: usize| i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    if i32at(0) != 84 || &b[4..8] != b"CORD" || i32at(88) != 84 {
        return Err(bad("first record is not an 84-byte CORD header"));
    }
    if i32at(4 + 4 + 4 * 19) != 24 || i32at(4 + 4 + 4 * 10) != 1 {
        return Err(bad("not CHARMM version 24 with unit cell"));
    }
    if i32at(92) != 164 || i32at(96) != 2 || i32at(260) != 164 || i32at(264) != 4 || i32at(272) != 4 {
        return Err(bad("title or atom-count record"));
    }
    let n_atoms = i32at(268);
    if n_atoms <= 0 {
        return Err(bad("atom count"));
    }
    let title = |o: usize| String::from_utf8_lossy(&b[o..o + 80]).trim_end().to_string();
    Ok(DcdHeader {
        n_atoms: n_atoms as usize,
        n_frames: i32at(8).max(0) as usize,
        istart: i32at(12),
        nsavc: i32at(16),
        delta: f32::from_le_bytes([b[44], b[45], b[46], b[47]]),
        titles: [title(100), title(180)],
    })
}

/// Reads a DCD written by [`DcdWriter`]: header and frames (Å, float32).
/// Frames are counted from the file size; a partial trailing frame is ignored.
pub fn read_dcd(path: &Path) -> Result<(DcdHeader, Vec<Vec<[f32; 3]>>)> {
    let bytes = std::fs::read(path).map_err(io_err(path))?;
    if (bytes.len() as u64) < HEADER_BYTES {
        return Err(Error::io(path.display().to_string(), format!("too short for a DCD header")));
    }
    let mut h = parse_header(path, &bytes[..HEADER_BYTES as usize])?;
    let n = h.n_atoms;
    let fb = frame_bytes(n) as usize;
    let count = (bytes.len() - HEADER_BYTES as usize) / fb;
    h.n_frames = count;
    let rec = |o: usize| i32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let mut frames = Vec::with_capacity(count);
    for f in 0..count {
        let base = HEADER_BYTES as usize + f * fb;
        if rec(base) != 48 || rec(base + 52) != 48 {
            return Err(Error::io(path.display().to_string(), format!("frame {f}: bad unit-cell record")));
        }
        let mut xyz = vec![[0f32; 3]; n];
        for a in 0..3 {
            let o = base + 56 + a * (8 + 4 * n);
            if rec(o) != (4 * n) as i32 || rec(o + 4 + 4 * n) != (4 * n) as i32 {
                return Err(Error::io(path.display().to_string(), format!("frame {f}: bad coordinate record")));
            }
            for (i, p) in xyz.iter_mut().enumerate() {
                let k = o + 4 + 4 * i;
                p[a] = f32::from_le_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
            }
        }
        frames.push(xyz);
    }
    Ok((h, frames))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::IntegrationParameters;
    use crate::material::Material;
    use crate::rod::RodBuilder;
    use crate::section::Section;
    use crate::spline::KnotKind;
    use nalgebra::Vector3;

    fn tmpdir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("strandkit-traj-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn world() -> World {
        let mut w = World::new(IntegrationParameters::default());
        let s = Section::circle(0.1).unwrap();
        let m = Material::preset("nylon").unwrap();
        let a = RodBuilder::straight(Vector3::zeros(), Vector3::new(5.0, 0.0, 0.0))
            .control_points(6)
            .section(s)
            .material(m.clone())
            .build()
            .unwrap();
        let b = RodBuilder::curve(6.0, |t| Vector3::new(t.cos(), t.sin(), 1.0))
            .control_points(8)
            .knots(KnotKind::Periodic)
            .section(s)
            .material(m)
            .build()
            .unwrap();
        w.add_rod(a);
        w.add_rod(b);
        w
    }

    #[test]
    fn topology_chains_and_bonds() {
        let w = world();
        let t = Topology::from_world(&w);
        assert_eq!(t.chains.len(), 2);
        assert_eq!(t.chains[0], Chain { beads: 3 * 5, closed: false, residues: vec![] });
        assert_eq!(t.chains[1], Chain { beads: 8 * 5, closed: true, residues: vec![] });
        let b = t.bonds();
        assert_eq!(b.len(), 14 + 40);
        assert_eq!(b[0], [0, 1]);
        assert_eq!(*b.last().unwrap(), [54, 15]);
        assert_eq!(bead_positions(&w).len(), 55);
    }

    #[test]
    fn named_residues_links_and_bfactors() {
        let chain = |r: &[&str]| Chain {
            beads: r.len(),
            closed: false,
            residues: r.iter().map(|x| x.to_string()).collect(),
        };
        let t = Topology::new(vec![chain(&["DG", "DA"]), chain(&["DT", "DC"])], vec![[0, 3], [1, 2]]).unwrap();
        assert_eq!(t.bonds(), vec![[0, 1], [2, 3], [0, 3], [1, 2]]);
        let p: Vec<[f64; 3]> = (0..4).map(|i| [i as f64, 0.0, 0.0]).collect();
        let s = pdb_string_marked(&t, &[p.clone()], 10.0, Some(&[0.0, 1.0, 1.0, 0.0])).unwrap();
        let atoms: Vec<&str> = s.lines().filter(|l| l.starts_with("HETATM")).collect();
        let names: Vec<&str> = atoms.iter().map(|l| l[17..20].trim()).collect();
        assert_eq!(names, ["DG", "DA", "DT", "DC"]);
        let beta: Vec<f64> = atoms.iter().map(|l| l[60..66].trim().parse().unwrap()).collect();
        assert_eq!(beta, [0.0, 1.0, 1.0, 0.0]);
        assert!(s.contains("CONECT    1    2    4\n"));
        assert!(psf_string(&t).unwrap().lines().any(|l| l.split_whitespace().nth(3) == Some("DC")));
        // Refused: a residue name PDB cannot hold, a link to no bead, a self
        // link, residue names not one per bead, B-factors of the wrong count.
        assert!(Topology::new(vec![chain(&["DNA1"])], vec![]).is_err());
        assert!(Topology::new(vec![chain(&["D A"])], vec![]).is_err());
        assert!(Topology::new(vec![chain(&["DA"])], vec![[0, 1]]).is_err());
        assert!(Topology::new(vec![chain(&["DA", "DT"])], vec![[1, 1]]).is_err());
        assert!(Topology::new(vec![chain(&["DA", "DT"])], vec![[1, 0]]).is_err()); // the backbone bond again
        assert!(Topology::new(vec![chain(&["DA"]), chain(&["DT"])], vec![[0, 1], [1, 0]]).is_err());
        let short = Chain { beads: 3, closed: false, residues: vec!["DA".into()] };
        assert!(Topology::new(vec![short], vec![]).is_err());
        assert!(pdb_string_marked(&t, &[p.clone()], 10.0, Some(&[0.0; 3])).is_err());
        assert!(pdb_string_marked(&t, &[p], 10.0, Some(&[0.0, f64::NAN, 0.0, 0.0])).is_err());
    }

    #[test]
    fn pdb_columns_chains_and_conect() {
        let w = world();
        let t = Topology::from_world(&w);
        let p = bead_positions(&w);
        let s = pdb_string(&t, &[p.clone()], 10.0).unwrap();
        let atoms: Vec<&str> = s.lines().filter(|l| l.starts_with("HETATM")).collect();
        assert_eq!(atoms.len(), 55);
        for (i, l) in atoms.iter().enumerate() {
            assert_eq!(l.len(), 80);
            assert_eq!(l[6..11].trim().parse::<usize>().unwrap(), i + 1);
            assert_eq!(&l[17..20], RESIDUE_NAME);
            assert_eq!(&l[76..78], " P");
            let x: f64 = l[30..38].trim().parse().unwrap();
            assert!((x - 10.0 * p[i][0]).abs() <= 5e-4);
        }
        assert_eq!(&atoms[0][21..22], "A");
        assert_eq!(&atoms[54][21..22], "B");
        assert_eq!(s.lines().filter(|l| *l == "TER").count(), 2);
        // Bead 16 (first of the ring) is bonded to 17 and to 55.
        assert!(s.contains("CONECT   16   17   55\n"));
        assert!(s.contains("CONECT    1    2\n"));
        // Two frames → MODEL records.
        let s2 = pdb_string(&t, &[p.clone(), p.clone()], 10.0).unwrap();
        assert_eq!(s2.matches("MODEL").count(), 2);
        // Out of the columns → a clear error.
        let e = pdb_string(&t, &[p.clone()], 1e10).unwrap_err();
        assert!(matches!(e, Error::InvalidInput { .. }) && e.to_string().contains("PSF + DCD"), "{e}");
        let mut bad = p.clone();
        bad[3][1] = f64::NAN;
        assert!(matches!(pdb_string(&t, &[bad], 1.0), Err(Error::InvalidInput { .. })));
        assert!(matches!(pdb_string(&t, &[p[..5].to_vec()], 1.0), Err(Error::InvalidInput { .. })));
    }

    #[test]
    fn psf_atoms_and_bonds() {
        let t = Topology::from_world(&world());
        let s = psf_string(&t).unwrap();
        assert!(s.starts_with("PSF\n"));
        assert!(s.contains("      55 !NATOM\n"));
        assert!(s.contains("      54 !NBOND: bonds\n"));
        let first = s.lines().find(|l| l.trim_start().starts_with("1 R0")).unwrap();
        let w: Vec<&str> = first.split_whitespace().collect();
        assert_eq!(w, ["1", "R0", "1", "SKB", "P", "P", "0.000000", "30.9700", "0"]);
        // VMD's fixed columns: segid at 9..13, resname at 19..23, mass at 48..62.
        assert_eq!(&first[9..11], "R0");
        assert_eq!(&first[19..22], "SKB");
        assert_eq!(first[48..62].trim(), "30.9700");
    }

    #[test]
    fn values_beyond_the_format_are_refused_and_nothing_is_written() {
        let d = tmpdir("range");
        let w = world();
        let t = Topology::from_world(&w);
        let p = bead_positions(&w);
        // PDB: 8.3 columns hold -999.999 ..= 9999.999 Å.
        for (x, fits) in [(9999.999, true), (-999.999, true), (9999.9996, false), (-1000.0, false), (1e300, false)] {
            let mut f = p.clone();
            f[4][2] = x;
            let path = d.join("r.pdb");
            let r = write_pdb(&path, &t, &[f], 1.0, None);
            if fits {
                r.unwrap();
                let s = std::fs::read_to_string(&path).unwrap();
                let line = s.lines().filter(|l| l.starts_with("HETATM")).nth(4).unwrap();
                assert_eq!((line.len(), line[46..54].trim().parse::<f64>().unwrap()), (80, x));
                std::fs::remove_file(&path).unwrap();
            } else {
                let e = r.unwrap_err();
                assert!(matches!(e, Error::InvalidInput { .. }) && e.to_string().contains("bead 4"), "{e}");
                assert!(std::fs::read_dir(&d).unwrap().next().is_none(), "nothing written for {x}");
            }
        }
        // DCD: float32 after the conversion to Å.
        let path = d.join("r.dcd");
        let hdr = DcdHeader { n_atoms: p.len(), n_frames: 0, istart: 0, nsavc: 1, delta: 1.0, titles: Default::default() };
        let mut wr = DcdWriter::create(&path, hdr).unwrap();
        wr.write_frame(&p, 10.0).unwrap();
        let size = std::fs::metadata(&path).unwrap().len();
        let mut big = p.clone();
        big[1][0] = 1e300; // finite in f64, inf in f32
        let e = wr.write_frame(&big, 1.0).unwrap_err();
        assert!(matches!(&e, Error::InvalidInput { what, .. } if what.contains("atom 1")), "{e}");
        big[1][0] = 1e37; // fits, but not once scaled to Å
        assert!(matches!(wr.write_frame(&big, 100.0), Err(Error::InvalidInput { .. })));
        big[1][0] = f64::INFINITY;
        assert!(matches!(wr.write_frame(&big, 1.0), Err(Error::InvalidInput { .. })));
        assert_eq!((wr.n_frames(), std::fs::metadata(&path).unwrap().len()), (1, size));
        // The largest float32 itself is still a value.
        big[1][0] = f32::MAX as f64;
        wr.write_frame(&big, 1.0).unwrap();
        wr.close().unwrap();
        let (h, frames) = read_dcd(&path).unwrap();
        assert_eq!((h.n_frames, frames[1][1][0]), (2, f32::MAX));
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn dcd_roundtrip_append_and_interruption() {
        let d = tmpdir("dcd");
        let path = d.join("t.dcd");
        let w = world();
        let p = bead_positions(&w);
        let hdr = DcdHeader {
            n_atoms: p.len(),
            n_frames: 0,
            istart: 0,
            nsavc: 10,
            delta: 1e-3,
            titles: ["strandkit test".into(), "second line".into()],
        };
        let mut wr = DcdWriter::create(&path, hdr).unwrap();
        for k in 0..3 {
            let f: Vec<[f64; 3]> = p.iter().map(|x| [x[0] + k as f64, x[1], x[2]]).collect();
            wr.write_frame(&f, 10.0).unwrap();
        }
        assert!(matches!(wr.write_frame(&p[..3], 10.0), Err(Error::InvalidInput { .. })));
        wr.close().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[4..8], b"CORD");
        assert_eq!(i32::from_le_bytes(bytes[8..12].try_into().unwrap()), 3); // NSET
        assert_eq!(i32::from_le_bytes(bytes[20..24].try_into().unwrap()), 20); // NSTEP of last frame
        assert_eq!(bytes.len() as u64, HEADER_BYTES + 3 * frame_bytes(55));
        let (h, frames) = read_dcd(&path).unwrap();
        assert_eq!((h.n_atoms, h.n_frames, h.nsavc, h.titles[0].as_str()), (55, 3, 10, "strandkit test"));
        for (k, f) in frames.iter().enumerate() {
            for (a, b) in f.iter().zip(&p) {
                assert_eq!(a[0], ((b[0] + k as f64) * 10.0) as f32);
                assert_eq!(a[2], (b[2] * 10.0) as f32);
            }
        }
        // An interrupted append (half a frame on disk) is still readable,
        // and reopening cuts the partial frame and carries on.
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&vec![7u8; 100]).unwrap();
        drop(f);
        assert_eq!(read_dcd(&path).unwrap().1.len(), 3);
        let mut wr = DcdWriter::open_append(&path).unwrap();
        assert_eq!(wr.n_frames(), 3);
        wr.write_frame(&p, 10.0).unwrap();
        wr.close().unwrap();
        let (h, frames) = read_dcd(&path).unwrap();
        assert_eq!((h.n_frames, frames.len()), (4, 4));
        assert_eq!(std::fs::metadata(&path).unwrap().len(), HEADER_BYTES + 4 * frame_bytes(55));
        // Not a DCD → an error, not a panic.
        std::fs::write(d.join("x.dcd"), b"hello").unwrap();
        assert!(matches!(DcdWriter::open_append(&d.join("x.dcd")), Err(Error::Io { .. })));
        assert!(matches!(read_dcd(&d.join("x.dcd")), Err(Error::Io { .. })));
        std::fs::remove_dir_all(&d).ok();
    }
}
