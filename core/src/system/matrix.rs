//! The KKT matrix as assembled (SPEC §4–5), in the storage its first
//! factorisation reads: band storage for narrow bands (the band LDLᵀ and LU
//! work in place), a sparse pattern for wide ones (a fabric's band is as
//! wide as its contact web: zeroing and reading n × (2 bw + 1) entries per
//! assembly cost more than the sparse factorisation itself). Assembly,
//! damping, equilibration and the residual checks go through this type, so
//! they do not depend on the storage.
use crate::linalg::band::{BandColumnsMut, BandMatrix};
use crate::linalg::csc::CscAssembly;

/// Where the entries live.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Storage {
    #[default]
    Band,
    Sparse,
}

#[derive(Clone, Debug, Default)]
pub struct KktMatrix {
    storage: Storage,
    bandwidth: usize,
    band: BandMatrix,
    csc: CscAssembly,
    /// In sparse storage, `band` holds the entries (made for a band
    /// factorisation tried after the sparse one).
    band_filled: bool,
}

impl KktMatrix {
    /// Starts an assembly of an `n × n` matrix of half-bandwidth
    /// `bandwidth`, all zero.
    /// `parallel`: the band's zeros are written on rayon's pool (large ones).
    pub fn reset(&mut self, n: usize, bandwidth: usize, storage: Storage, parallel: bool) {
        self.storage = storage;
        self.bandwidth = bandwidth;
        self.band_filled = false;
        match storage {
            Storage::Band => self.band.reshape_on(n, bandwidth, bandwidth, parallel),
            Storage::Sparse => self.csc.begin(n),
        }
    }

    pub fn storage(&self) -> Storage {
        self.storage
    }

    pub fn n(&self) -> usize {
        match self.storage {
            Storage::Band => self.band.n(),
            Storage::Sparse => self.csc.n(),
        }
    }

    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        match self.storage {
            Storage::Band => self.band.add(i, j, v),
            Storage::Sparse => self.csc.add(i, j, v),
        }
    }

    /// A symmetric block given by its upper half (see `BandMatrix::add_sym_block`).
    #[inline]
    pub fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        match self.storage {
            Storage::Band => self.band.add_sym_block(idx, upper, stride),
            Storage::Sparse => self.csc.add_sym_block(idx, upper, stride),
        }
    }

    /// In band storage, columns `..c` and `c..` apart (see
    /// [`BandMatrix::split_columns_mut`]); None in sparse storage.
    pub fn split_band_columns(&mut self, c: usize) -> Option<(BandColumnsMut<'_>, BandColumnsMut<'_>)> {
        (self.storage == Storage::Band).then(|| self.band.split_columns_mut(c))
    }

    /// Ends the assembly (sums a sparse assembly into its pattern); the
    /// reads below need it.
    pub fn finish(&mut self) {
        if self.storage == Storage::Sparse {
            self.csc.finish();
        }
    }

    /// Entry (i, j).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match self.storage {
            Storage::Band => self.band.get(i, j),
            Storage::Sparse => self.csc.get(i, j),
        }
    }

    #[inline]
    pub fn diag(&self, i: usize) -> f64 {
        match self.storage {
            Storage::Band => self.band.get(i, i),
            Storage::Sparse => self.csc.diag(i),
        }
    }

    /// `A[i][i] += v` after the assembly.
    pub fn add_diag(&mut self, i: usize, v: f64) {
        self.band_filled = false;
        match self.storage {
            Storage::Band => self.band.add(i, i, v),
            Storage::Sparse => self.csc.add_diag(i, v),
        }
    }

    /// `f(i, A[i][j])` over the stored entries of column j.
    pub fn for_column(&self, j: usize, mut f: impl FnMut(usize, f64)) {
        match self.storage {
            Storage::Band => {
                let (i0, col) = self.band.column(j);
                col.iter().enumerate().for_each(|(r, &v)| f(i0 + r, v));
            }
            Storage::Sparse => {
                let (rows, vals) = self.csc.column(j);
                rows.iter().zip(vals).for_each(|(&i, &v)| f(i, v));
            }
        }
    }

    /// `f(j, A[i][j])` over the stored entries of row i.
    pub fn for_row(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        match self.storage {
            Storage::Band => {
                let (j0, row) = self.band.row(i);
                row.enumerate().for_each(|(c, v)| f(j0 + c, v));
            }
            Storage::Sparse => self.csc.row(i).for_each(|(j, v)| f(j, v)),
        }
    }

    /// A ← D A D (a large band on rayon's pool when `parallel`).
    pub fn scale_symmetric(&mut self, d: &[f64], parallel: bool) {
        self.band_filled = false;
        match self.storage {
            Storage::Band => self.band.scale_symmetric_on(d, parallel),
            Storage::Sparse => self.csc.scale_symmetric(d),
        }
    }

    /// y = A x.
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        match self.storage {
            Storage::Band => self.band.matvec(x, y),
            Storage::Sparse => self.csc.matvec(x, y),
        }
    }

    /// The matrix in band storage, for the band factorisations (made from
    /// the sparse entries once per assembly in sparse storage).
    pub fn band(&mut self) -> &BandMatrix {
        if self.storage == Storage::Sparse && !self.band_filled {
            // The layout's width (its size is what the caller checked); the
            // pattern may keep zeros of earlier assemblies beyond it.
            let (n, w) = (self.csc.n(), self.bandwidth);
            self.band.reshape(n, w, w);
            for j in 0..n {
                let (rows, vals) = self.csc.column(j);
                for (&i, &v) in rows.iter().zip(vals) {
                    if v != 0.0 && self.band.in_band(i, j) {
                        self.band.set(i, j, v);
                    }
                }
            }
            self.band_filled = true;
        }
        &self.band
    }

    /// The entries in band storage, when that is where they live.
    pub fn as_band(&self) -> Option<&BandMatrix> {
        (self.storage == Storage::Band || self.band_filled).then_some(&self.band)
    }

    /// The sparse assembly, when that is where the entries live.
    pub fn as_csc(&self) -> Option<&CscAssembly> {
        (self.storage == Storage::Sparse).then_some(&self.csc)
    }
}
