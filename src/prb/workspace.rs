//! A PRB chain solver's scratch storage: the workspace of one path solve, handed out as
//! named slices, and the small inline buffer it and the path's configurations live in (so a
//! fit's trial models allocate nothing per path).

/// `len` numbers, zeros at first: inline up to `N`, so that making, copying and dropping one
/// allocates nothing, and on the heap beyond.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Inline<const N: usize> {
    len: usize,
    inline: [f64; N],
    heap: Vec<f64>,
}

impl<const N: usize> Inline<N> {
    pub(super) fn zeros(len: usize) -> Inline<N> {
        Inline {
            len,
            inline: [0.0; N],
            heap: if len > N { vec![0.0; len] } else { Vec::new() },
        }
    }
}

impl<const N: usize> std::ops::Deref for Inline<N> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        match self.len {
            len if len <= N => &self.inline[..len],
            _ => &self.heap,
        }
    }
}

impl<const N: usize> std::ops::DerefMut for Inline<N> {
    fn deref_mut(&mut self) -> &mut [f64] {
        match self.len {
            len if len <= N => &mut self.inline[..len],
            _ => &mut self.heap,
        }
    }
}

/// Scratch space for one path solve, so Newton allocates nothing: one buffer (inline for
/// small chains), handed out as named slices by [`Workspace::parts`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Workspace {
    /// Segments.
    pub(super) n: usize,
    /// Degrees of freedom.
    pub(super) m: usize,
    /// Inline for a chain of up to five segments and four degrees of freedom (64 numbers:
    /// every path of a 3R or 4R fit's trial models solves without allocating).
    pub(super) buf: Inline<64>,
}

/// A [`Workspace`]'s slices: `n` per segment, then `res` and `step` (`m`) and `jac` (`m * m`).
pub(super) struct Parts<'a> {
    pub(super) theta_cum: &'a mut [f64],
    /// `sin` and `cos` of `theta_cum`, as `PrbSolver::residual` last left them.
    pub(super) sin: &'a mut [f64],
    pub(super) cos: &'a mut [f64],
    pub(super) length: &'a mut [f64],
    pub(super) axial: &'a mut [f64],
    pub(super) transverse: &'a mut [f64],
    pub(super) suffix_q: &'a mut [f64],
    pub(super) suffix_n: &'a mut [f64],
    pub(super) res: &'a mut [f64],
    pub(super) step: &'a mut [f64],
    pub(super) jac: &'a mut [f64],
}

impl Workspace {
    /// Per-segment slices of a workspace.
    const SEGMENT_SLICES: usize = 8;

    pub(super) fn new(n: usize, m: usize) -> Workspace {
        Workspace {
            n,
            m,
            buf: Inline::zeros(Self::SEGMENT_SLICES * n + 2 * m + m * m),
        }
    }

    /// The last slice of [`Workspace::parts`], `jac` (`m * m`), to read.
    pub(super) fn jac(&self) -> &[f64] {
        &self.buf[Self::SEGMENT_SLICES * self.n + 2 * self.m..]
    }

    pub(super) fn parts(&mut self) -> Parts<'_> {
        let (n, m) = (self.n, self.m);
        let (theta_cum, rest) = self.buf.split_at_mut(n);
        let (sin, rest) = rest.split_at_mut(n);
        let (cos, rest) = rest.split_at_mut(n);
        let (length, rest) = rest.split_at_mut(n);
        let (axial, rest) = rest.split_at_mut(n);
        let (transverse, rest) = rest.split_at_mut(n);
        let (suffix_q, rest) = rest.split_at_mut(n);
        let (suffix_n, rest) = rest.split_at_mut(n);
        let (res, rest) = rest.split_at_mut(m);
        let (step, jac) = rest.split_at_mut(m);
        Parts {
            theta_cum,
            sin,
            cos,
            length,
            axial,
            transverse,
            suffix_q,
            suffix_n,
            res,
            step,
            jac,
        }
    }
}
