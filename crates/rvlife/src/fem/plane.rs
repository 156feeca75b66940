//! Plane-stress finite elements: isoparametric 6-node triangles, assembly with prescribed
//! displacements and rigid spiders (master-slave constraints), sparse Cholesky solve (faer),
//! stress recovery.
//!
//! Source: Zienkiewicz, Taylor & Zhu, *The Finite Element Method: Its Basis and Fundamentals*,
//! 7th ed., ch. 6 (plane elasticity) and ch. 5 (quadratic triangles); 6-point Gauss rule of
//! Dunavant (1985), exact to degree 4.

use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Mat, MatRef, Side};

use crate::error::{Error, Result};
use crate::fem::mesh::Mesh;
use crate::geometry::Vec2;

/// Linear-elastic isotropic material in plane stress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneStress {
    /// Young's modulus, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Thickness, m.
    pub thickness: f64,
}

impl PlaneStress {
    /// Elasticity matrix `D` (Pa) relating `(sx, sy, txy)` to `(ex, ey, gxy)`.
    pub fn d(&self) -> [[f64; 3]; 3] {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let c = e / (1.0 - nu * nu);
        [
            [c, c * nu, 0.0],
            [c * nu, c, 0.0],
            [0.0, 0.0, c * 0.5 * (1.0 - nu)],
        ]
    }
}

/// 6-point Gauss rule on the reference triangle (Dunavant 1985, degree 4): `(xi, eta, weight)`
/// with weights summing to the reference area 1/2.
const GAUSS6: [(f64, f64, f64); 6] = {
    const A: f64 = 0.445_948_490_915_965;
    const WA: f64 = 0.223_381_589_678_011 * 0.5;
    const B: f64 = 0.091_576_213_509_771;
    const WB: f64 = 0.109_951_743_655_322 * 0.5;
    [
        (A, A, WA),
        (1.0 - 2.0 * A, A, WA),
        (A, 1.0 - 2.0 * A, WA),
        (B, B, WB),
        (1.0 - 2.0 * B, B, WB),
        (B, 1.0 - 2.0 * B, WB),
    ]
};

/// Natural coordinates of the six nodes.
const NODE_XI: [(f64, f64); 6] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (0.5, 0.0),
    (0.5, 0.5),
    (0.0, 0.5),
];

/// Derivatives of the six quadratic shape functions with respect to `(xi, eta)`.
fn shape_derivatives(xi: f64, eta: f64) -> [[f64; 2]; 6] {
    let l1 = 1.0 - xi - eta;
    [
        [-(4.0 * l1 - 1.0), -(4.0 * l1 - 1.0)],
        [4.0 * xi - 1.0, 0.0],
        [0.0, 4.0 * eta - 1.0],
        [4.0 * (l1 - xi), -4.0 * xi],
        [4.0 * eta, 4.0 * xi],
        [-4.0 * eta, 4.0 * (l1 - eta)],
    ]
}

/// Shape functions of a 3-node (quadratic) edge at `s` in `[-1, 1]`: start, end, mid.
pub(crate) fn edge_shape(s: f64) -> [f64; 3] {
    [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s]
}

/// Derivatives of [`edge_shape`] with respect to `s`.
pub(crate) fn edge_shape_derivative(s: f64) -> [f64; 3] {
    [s - 0.5, s + 0.5, -2.0 * s]
}

/// Cartesian shape-function gradients and Jacobian determinant at `(xi, eta)`.
fn gradients(x: &[Vec2; 6], xi: f64, eta: f64) -> ([[f64; 2]; 6], f64) {
    let dn = shape_derivatives(xi, eta);
    let (mut j11, mut j12, mut j21, mut j22) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..6 {
        j11 += dn[k][0] * x[k].x;
        j12 += dn[k][0] * x[k].y;
        j21 += dn[k][1] * x[k].x;
        j22 += dn[k][1] * x[k].y;
    }
    let det = j11 * j22 - j12 * j21;
    let mut g = [[0.0; 2]; 6];
    for k in 0..6 {
        g[k][0] = (j22 * dn[k][0] - j12 * dn[k][1]) / det;
        g[k][1] = (-j21 * dn[k][0] + j11 * dn[k][1]) / det;
    }
    (g, det)
}

/// Element stiffness (12 x 12, dofs `u0x, u0y, u1x, ...`), N/m.
///
/// # Errors
/// [`Error::Numerical`] for an inverted or degenerate element.
pub(crate) fn element_stiffness(x: &[Vec2; 6], mat: &PlaneStress) -> Result<[[f64; 12]; 12]> {
    let d = mat.d();
    let mut k = [[0.0; 12]; 12];
    for &(xi, eta, w) in &GAUSS6 {
        let (g, det) = gradients(x, xi, eta);
        if det <= 0.0 || !det.is_finite() {
            return Err(Error::numerical("plane-stress element", "inverted element"));
        }
        let f = w * det * mat.thickness;
        // D B for each node column pair, then B^T (D B).
        for a in 0..6 {
            let (ax, ay) = (g[a][0], g[a][1]);
            // Rows of B for node a: [ax 0; 0 ay; ay ax].
            for b in 0..6 {
                let (bx, by) = (g[b][0], g[b][1]);
                // D B_b columns.
                let db_x = [d[0][0] * bx, d[1][0] * bx, d[2][2] * by];
                let db_y = [d[0][1] * by, d[1][1] * by, d[2][2] * bx];
                k[2 * a][2 * b] += f * (ax * db_x[0] + ay * db_x[2]);
                k[2 * a][2 * b + 1] += f * (ax * db_y[0] + ay * db_y[2]);
                k[2 * a + 1][2 * b] += f * (ay * db_x[1] + ax * db_x[2]);
                k[2 * a + 1][2 * b + 1] += f * (ay * db_y[1] + ax * db_y[2]);
            }
        }
    }
    Ok(k)
}

/// Shape functions of the 6-node triangle at `(xi, eta)`: corners, then the mid-edge nodes
/// 0-1, 1-2, 2-0.
fn shape_functions(xi: f64, eta: f64) -> [f64; 6] {
    let l1 = 1.0 - xi - eta;
    [
        l1 * (2.0 * l1 - 1.0),
        xi * (2.0 * xi - 1.0),
        eta * (2.0 * eta - 1.0),
        4.0 * l1 * xi,
        4.0 * xi * eta,
        4.0 * eta * l1,
    ]
}

/// Consistent element mass (6 x 6 per displacement component, the same for `x` and `y`), kg:
/// `rho t int N_a N_b dA`, exact for straight-sided elements with the degree-4 rule
/// (Zienkiewicz, Taylor & Zhu, ch. 16).
///
/// # Errors
/// [`Error::Numerical`] for an inverted or degenerate element.
pub(crate) fn element_mass(x: &[Vec2; 6], density: f64, thickness: f64) -> Result<[[f64; 6]; 6]> {
    let mut m = [[0.0; 6]; 6];
    for &(xi, eta, w) in &GAUSS6 {
        let (_, det) = gradients(x, xi, eta);
        if det <= 0.0 || !det.is_finite() {
            return Err(Error::numerical("plane-stress element", "inverted element"));
        }
        let n = shape_functions(xi, eta);
        let f = w * det * density * thickness;
        for a in 0..6 {
            for b in 0..6 {
                m[a][b] += f * n[a] * n[b];
            }
        }
    }
    Ok(m)
}

/// A rigid spider: a master point whose three degrees of freedom `(ux, uy, rotation)` carry the
/// nodes tied to it, `u = u_m + theta e_z x (x - x_m)` (the paper's rigid point at a bore).
#[derive(Debug, Clone, Copy)]
pub struct Spider {
    /// Master point, m.
    pub centre: Vec2,
    /// Prescribed values of `(ux m, uy m, rotation rad)`; `None` leaves the dof free.
    pub fixed: [Option<f64>; 3],
}

/// Boundary condition of one node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeBc {
    /// Both components free.
    Free,
    /// Prescribed `(ux, uy)`, m; `None` leaves that component free.
    Fixed(Option<f64>, Option<f64>),
    /// Tied to spider `k`.
    Spider(usize),
}

/// One node displacement component as `sum coeff * x[eq] + constant`.
#[derive(Debug, Clone, Default)]
struct DofExpr {
    terms: Vec<(usize, f64)>,
    constant: f64,
}

/// An assembled and factorised plane-stress model.
pub struct FeModel {
    /// The mesh.
    pub mesh: Mesh,
    /// Material.
    pub material: PlaneStress,
    /// Spiders.
    pub spiders: Vec<Spider>,
    dofs: Vec<DofExpr>,
    equations: usize,
    lift: Vec<f64>,
    llt: Factor,
    assembly: std::sync::Arc<Assembly>,
}

/// The assembly pattern of a stiffness matrix: its sparsity and the order that sums the element
/// entries (in assembly order) into it (faer's `Argsort`), shared by the models of a mesh moved
/// without changing its elements or equations.
struct Assembly {
    pattern: SymbolicSparseColMat<usize>,
    order: Argsort<usize>,
}

/// Loads per block of `Factor::condense`'s products.
pub(crate) const CONDENSE_BLOCK: usize = 32;

/// Clears the upper halves of the vector registers (`vzeroupper`) on a CPU with AVX, after a
/// call into faer. faer's matrix kernels (hand-written AVX-512) return without it; the thread's
/// later SSE code (all of rvlife's, built for baseline x86-64) then pays the AVX-SSE transition
/// penalty, and on CPUs whose glibc prefers no `vzeroupper` of its own every call of `pow`,
/// `log`, `sin` or `cos` paid it for the rest of the run: the built-in study took 2 to 4 times
/// as long with the flexible disc on. No effect on any result; a no-op elsewhere.
#[inline]
pub(crate) fn clear_upper_simd() {
    // A build for AVX gets `vzeroupper` from the compiler wherever it is due.
    #[cfg(all(target_arch = "x86_64", not(target_feature = "avx")))]
    if std::arch::is_x86_feature_detected!("avx") {
        /// `vzeroupper` through its intrinsic, so that the compiler knows what it clears.
        #[target_feature(enable = "avx")]
        unsafe fn zero_upper() {
            std::arch::x86_64::_mm256_zeroupper();
        }
        // SAFETY: the CPU has AVX, checked just above.
        unsafe { zero_upper() }
    }
}

/// Sparse Cholesky factor `P K P^T = L L^T` of a stiffness matrix (faer's symbolic analysis
/// with its approximate-minimum-degree ordering `P`, simplicial so that the columns of `L` and
/// its elimination tree can be read by `Factor::condense`).
pub struct Factor {
    symbolic: std::sync::Arc<Symbolic>,
    values: Vec<f64>,
}

/// The symbolic part of a [`Factor`], shared by the factors of stiffness matrices with one
/// sparsity pattern (a mesh moved without changing its topology).
struct Symbolic {
    chol: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    /// Elimination-tree parent of each column of `L` (`usize::MAX` at a root).
    parent: Vec<usize>,
    /// Position in `L` of original equation `q`: `inv[q]` (identity when faer kept the order).
    inv: Vec<usize>,
    /// Non-zeros of the lower triangle of the matrix analysed.
    nnz: usize,
}

impl Factor {
    /// Factorises the symmetric positive definite `k` (lower triangle stored), with the
    /// symbolic analysis of `reuse` when given and made for the same sparsity pattern.
    ///
    /// # Errors
    /// The faer error's text when the analysis fails or `k` is not positive definite.
    fn new(
        k: faer::sparse::SparseColMatRef<'_, usize, f64>,
        reuse: Option<&Factor>,
    ) -> std::result::Result<Factor, String> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        let nnz = k.compute_nnz();
        let symbolic = match reuse {
            Some(f) if f.symbolic.nnz == nnz && f.symbolic.chol.nrows() == k.nrows() => {
                f.symbolic.clone()
            }
            _ => std::sync::Arc::new(Self::analyse(k, nnz)?),
        };
        let mut values = vec![0.0; symbolic.chol.len_val()];
        let par = faer::Par::Seq;
        let mut mem = MemBuffer::try_new(
            symbolic
                .chol
                .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|e| format!("{e:?}"))?;
        symbolic
            .chol
            .factorize_numeric_llt::<f64>(
                &mut values,
                k,
                Side::Lower,
                faer::linalg::cholesky::llt::factor::LltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| format!("{e:?}"))?;
        Ok(Factor { symbolic, values })
    }

    /// The symbolic analysis of `k` (`nnz` non-zeros in its lower triangle).
    fn analyse(
        k: faer::sparse::SparseColMatRef<'_, usize, f64>,
        nnz: usize,
    ) -> std::result::Result<Symbolic, String> {
        use faer::sparse::linalg::cholesky::{
            factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw,
            SymmetricOrdering,
        };
        use faer::sparse::linalg::SupernodalThreshold;
        let chol = factorize_symbolic_cholesky(
            k.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .map_err(|e| format!("{e:?}"))?;
        let n = k.nrows();
        let SymbolicCholeskyRaw::Simplicial(s) = chol.raw() else {
            return Err(
                "faer returned a supernodal factor where a simplicial one was asked".into(),
            );
        };
        let (cp, ri) = (s.col_ptr(), s.row_idx());
        // Row indices are sorted within each column with the diagonal first; the first
        // sub-diagonal row is the column's parent in the elimination tree.
        let parent = (0..n)
            .map(|j| {
                if cp[j + 1] > cp[j] + 1 {
                    ri[cp[j] + 1]
                } else {
                    usize::MAX
                }
            })
            .collect();
        let inv = match chol.perm() {
            Some(p) => p.arrays().1.to_vec(),
            None => (0..n).collect(),
        };
        Ok(Symbolic {
            chol,
            parent,
            inv,
            nnz,
        })
    }

    /// Solves `K x = rhs` for the columns of `rhs` (`n x m`) in place.
    fn solve_in_place(&self, rhs: faer::MatMut<'_, f64>) {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::cholesky::LltRef;
        let par = faer::Par::Seq;
        let mut mem = MemBuffer::new(
            self.symbolic
                .chol
                .solve_in_place_scratch::<f64>(rhs.ncols(), par),
        );
        LltRef::new(&self.symbolic.chol, &self.values).solve_in_place_with_conj(
            faer::Conj::No,
            rhs,
            par,
            MemStack::new(&mut mem),
        );
    }

    /// `Y = L^-1 P B` for a block of sparse loads `B` (each `(equation, value)` pairs): the
    /// columns of `L` reached from the loads' entries up the elimination tree (their union,
    /// ascending: a topological order of the tree) and `Y` on them, row-major (`rows x loads`).
    /// One sweep over the union serves every load of the block, the update of a column applied
    /// to all of them at once (Gilbert and Peierls, 1988; T. A. Davis, *Direct Methods for Sparse
    /// Linear Systems*, SIAM 2006, section 3.2); each load's entries are those of its own
    /// sparse solve (zero off its reach, the same operations in the same order on it). `pos`
    /// (`n` entries of `usize::MAX`) is returned so.
    fn forward_block(
        &self,
        loads: &[Vec<(usize, f64)>],
        pos: &mut [usize],
    ) -> (Vec<usize>, Vec<f64>) {
        use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
        let SymbolicCholeskyRaw::Simplicial(s) = self.symbolic.chol.raw() else {
            unreachable!("Factor::analyse keeps a simplicial factor")
        };
        let (cp, ri) = (s.col_ptr(), s.row_idx());
        let nb = loads.len();
        let mut rows: Vec<usize> = Vec::with_capacity(2048);
        for b in loads {
            for &(q, _) in b {
                let mut j = self.symbolic.inv[q];
                // The tree path above a reached column is reached: stop where a walk went.
                while j != usize::MAX && pos[j] == usize::MAX {
                    pos[j] = 0;
                    rows.push(j);
                    j = self.symbolic.parent[j];
                }
            }
        }
        rows.sort_unstable();
        for (r, &j) in rows.iter().enumerate() {
            pos[j] = r;
        }
        let mut y = vec![0.0; rows.len() * nb];
        for (c, b) in loads.iter().enumerate() {
            for &(q, v) in b {
                y[pos[self.symbolic.inv[q]] * nb + c] += v;
            }
        }
        for (r, &j) in rows.iter().enumerate() {
            let (start, end) = (cp[j], cp[j + 1]);
            let (done, rest) = y.split_at_mut((r + 1) * nb);
            let yj = &mut done[r * nb..];
            let d = self.values[start];
            for x in yj.iter_mut() {
                *x /= d;
            }
            for p in start + 1..end {
                // Rows of column j lie above it in the tree, so in the union, after row r.
                let i = pos[ri[p]] - r - 1;
                let l = self.values[p];
                for (w, x) in rest[i * nb..(i + 1) * nb].iter_mut().zip(yj.iter()) {
                    *w -= l * *x;
                }
            }
        }
        for &j in &rows {
            pos[j] = usize::MAX;
        }
        (rows, y)
    }

    /// Compliance between sparse loads, `C = B K^-1 B^T` (`m x m`, row-major, m/N for loads in
    /// N and displacements in m): with `K = P^T L L^T P`, `C = Y^T Y` for `Y = L^-1 P B^T`,
    /// computed over elimination-tree reaches only ([`Factor`]; a load on a few outline nodes of
    /// the built-in disc reaches about 730 of its 39 530 columns). The loads are taken in blocks
    /// of [`CONDENSE_BLOCK`] consecutive ones (neighbours on the outline share most of their
    /// reach): each block's columns of `Y` in one sweep over the union of their reaches
    /// ([`Factor::forward_block`]), then each pair of blocks multiplied over the rows common to
    /// both (gathered contiguous, faer's `matmul`). Symmetric by construction; in parallel.
    pub(crate) fn condense(&self, loads: &[Vec<(usize, f64)>]) -> Vec<f64> {
        use faer::linalg::matmul::matmul;
        use faer::{Accum, Par};
        use rayon::prelude::*;
        let n = self.symbolic.parent.len();
        let m = loads.len();
        // Per block: the sorted union of its reaches and its columns dense over it.
        let blocks: Vec<(Vec<usize>, Vec<f64>, usize)> = loads
            .par_chunks(CONDENSE_BLOCK)
            .map_init(
                || vec![usize::MAX; n],
                |pos, chunk| {
                    let (rows, y) = self.forward_block(chunk, pos);
                    (rows, y, chunk.len())
                },
            )
            .collect();
        let pairs: Vec<(usize, usize)> = (0..blocks.len())
            .flat_map(|g| (0..=g).map(move |h| (g, h)))
            .collect();
        let products: Vec<Mat<f64>> = pairs
            .par_iter()
            .map_init(
                || (Vec::new(), Vec::new()),
                |(a, b), &(g, h)| {
                    let ((rg, yg, ng), (rh, yh, nh)) = (&blocks[g], &blocks[h]);
                    let (ng, nh) = (*ng, *nh);
                    // The rows common to both blocks, gathered contiguous (row-major).
                    a.clear();
                    b.clear();
                    let (mut i, mut k) = (0, 0);
                    while i < rg.len() && k < rh.len() {
                        match rg[i].cmp(&rh[k]) {
                            std::cmp::Ordering::Less => i += 1,
                            std::cmp::Ordering::Greater => k += 1,
                            std::cmp::Ordering::Equal => {
                                a.extend_from_slice(&yg[i * ng..(i + 1) * ng]);
                                b.extend_from_slice(&yh[k * nh..(k + 1) * nh]);
                                i += 1;
                                k += 1;
                            }
                        }
                    }
                    let common = a.len() / ng;
                    let av = MatRef::from_row_major_slice(a.as_slice(), common, ng);
                    let bv = MatRef::from_row_major_slice(b.as_slice(), common, nh);
                    let mut out = Mat::<f64>::zeros(ng, nh);
                    matmul(&mut out, Accum::Replace, av.transpose(), bv, 1.0, Par::Seq);
                    clear_upper_simd();
                    out
                },
            )
            .collect();
        let mut c = vec![0.0; m * m];
        for (&(g, h), p) in pairs.iter().zip(&products) {
            let (g0, h0) = (g * CONDENSE_BLOCK, h * CONDENSE_BLOCK);
            for r in 0..p.nrows() {
                for k in 0..p.ncols() {
                    c[(g0 + r) * m + h0 + k] = p[(r, k)];
                    c[(h0 + k) * m + g0 + r] = p[(r, k)];
                }
            }
        }
        c
    }
}

impl std::fmt::Debug for FeModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FeModel")
            .field("nodes", &self.mesh.nodes.len())
            .field("triangles", &self.mesh.triangles.len())
            .field("equations", &self.equations)
            .finish()
    }
}

/// Stress state at the mesh nodes (node-averaged), Pa.
#[derive(Debug, Clone)]
pub struct NodalStress {
    /// `(sx, sy, txy)` at every node, Pa.
    pub stress: Vec<[f64; 3]>,
}

impl NodalStress {
    /// Von Mises stress of node `i` (plane stress), Pa.
    pub(crate) fn von_mises(&self, i: usize) -> f64 {
        let [sx, sy, t] = self.stress[i];
        (sx * sx - sx * sy + sy * sy + 3.0 * t * t).max(0.0).sqrt()
    }
}

impl FeModel {
    /// Assembles the stiffness of `mesh` with boundary conditions `bc` (one per node) and the
    /// spiders, and factorises it (sparse Cholesky, faer, AMD ordering).
    ///
    /// # Errors
    /// [`Error::Invalid`] if `bc` does not match the mesh; [`Error::Numerical`] for an inverted
    /// element or a stiffness that is not positive definite (rigid-body motion left free).
    pub fn new(
        mesh: Mesh,
        material: PlaneStress,
        bc: &[NodeBc],
        spiders: Vec<Spider>,
    ) -> Result<FeModel> {
        Self::new_reusing(mesh, material, bc, spiders, None)
    }

    /// [`FeModel::new`] reusing the symbolic factorisation of `reuse`, a model of a mesh with
    /// the same nodes, elements and boundary conditions (moved nodes keep the sparsity
    /// pattern); analysed afresh when the pattern's size differs.
    ///
    /// # Errors
    /// As [`FeModel::new`].
    pub(crate) fn new_reusing(
        mesh: Mesh,
        material: PlaneStress,
        bc: &[NodeBc],
        spiders: Vec<Spider>,
        reuse: Option<&FeModel>,
    ) -> Result<FeModel> {
        if bc.len() != mesh.nodes.len() {
            return Err(Error::invalid(
                "fem boundary conditions",
                bc.len().to_string(),
                format!("one per node ({})", mesh.nodes.len()),
            ));
        }
        let mut eq = 0usize;
        let next = |eq: &mut usize| {
            *eq += 1;
            *eq - 1
        };
        let mut spider_dofs: Vec<[DofExpr; 3]> = Vec::with_capacity(spiders.len());
        for s in &spiders {
            let mut d: [DofExpr; 3] = Default::default();
            for (c, dof) in d.iter_mut().enumerate() {
                match s.fixed[c] {
                    Some(v) => dof.constant = v,
                    None => dof.terms.push((next(&mut eq), 1.0)),
                }
            }
            spider_dofs.push(d);
        }
        let mut dofs = Vec::with_capacity(2 * mesh.nodes.len());
        for (i, b) in bc.iter().enumerate() {
            match *b {
                NodeBc::Free => {
                    dofs.push(DofExpr {
                        terms: vec![(next(&mut eq), 1.0)],
                        constant: 0.0,
                    });
                    dofs.push(DofExpr {
                        terms: vec![(next(&mut eq), 1.0)],
                        constant: 0.0,
                    });
                }
                NodeBc::Fixed(ux, uy) => {
                    for v in [ux, uy] {
                        dofs.push(match v {
                            Some(v) => DofExpr {
                                terms: vec![],
                                constant: v,
                            },
                            None => DofExpr {
                                terms: vec![(next(&mut eq), 1.0)],
                                constant: 0.0,
                            },
                        });
                    }
                }
                NodeBc::Spider(k) => {
                    let s = spiders.get(k).ok_or_else(|| {
                        Error::invalid("fem spider", k.to_string(), "an existing spider")
                    })?;
                    let r = mesh.nodes[i] - s.centre;
                    let m = &spider_dofs[k];
                    // ux = ux_m - theta ry; uy = uy_m + theta rx.
                    for (c, lever) in [(0usize, -r.y), (1usize, r.x)] {
                        let mut e = m[c].clone();
                        for &(q, a) in &m[2].terms {
                            e.terms.push((q, a * lever));
                        }
                        e.constant += m[2].constant * lever;
                        dofs.push(e);
                    }
                }
            }
        }
        let equations = eq;
        let mut lift = vec![0.0; equations];
        // The entries fall on the places of `reuse`'s where the elements and each dof's
        // equations are the same (a moved mesh): its pattern then serves.
        let shared = reuse
            .filter(|r| {
                r.mesh.triangles == mesh.triangles
                    && r.dofs.len() == dofs.len()
                    && r.dofs.iter().zip(&dofs).all(|(a, b)| {
                        a.terms.len() == b.terms.len()
                            && a.terms.iter().zip(&b.terms).all(|(x, y)| x.0 == y.0)
                    })
            })
            .map(|r| r.assembly.clone());
        let mut entries: Vec<Pair<usize, usize>> = Vec::new();
        let mut values: Vec<f64> = Vec::with_capacity(mesh.triangles.len() * 78);
        for t in &mesh.triangles {
            let x: [Vec2; 6] = std::array::from_fn(|k| mesh.nodes[t[k]]);
            let ke = element_stiffness(&x, &material)?;
            for a in 0..12 {
                let da = &dofs[2 * t[a / 2] + a % 2];
                for b in 0..12 {
                    let db = &dofs[2 * t[b / 2] + b % 2];
                    let k = ke[a][b];
                    for &(qa, ca) in &da.terms {
                        if db.constant != 0.0 {
                            lift[qa] -= ca * k * db.constant;
                        }
                        for &(qb, cb) in &db.terms {
                            if qa >= qb {
                                if shared.is_none() {
                                    entries.push(Pair::new(qa, qb));
                                }
                                values.push(ca * cb * k);
                            }
                        }
                    }
                }
            }
        }
        let assembly = match shared {
            Some(a) => a,
            None => {
                let (pattern, order) =
                    SymbolicSparseColMat::try_new_from_indices(equations, equations, &entries)
                        .map_err(|e| Error::numerical("fem assembly", format!("{e:?}")))?;
                std::sync::Arc::new(Assembly { pattern, order })
            }
        };
        drop(entries);
        let k = SparseColMat::<usize, f64>::new_from_argsort(
            assembly.pattern.clone(),
            &assembly.order,
            &values,
        )
        .map_err(|e| Error::numerical("fem assembly", format!("{e:?}")))?;
        drop(values);
        let llt = Factor::new(k.as_ref(), reuse.map(|f| &f.llt)).map_err(|e| {
            Error::numerical(
                "fem solve",
                format!("stiffness not positive definite ({e:?}): the disc is not held"),
            )
        })?;
        Ok(FeModel {
            mesh,
            material,
            spiders,
            dofs,
            equations,
            lift,
            llt,
            assembly,
        })
    }

    /// Consistent mass matrix on the equations (`equations x equations`, both triangles,
    /// kg and kg m for spider rotations) of the disc at `density` (kg/m^3): the element masses
    /// ([`element_mass`]) assembled through the same constraints as the stiffness (nodes on a
    /// spider move with it).
    ///
    /// # Errors
    /// [`Error::Numerical`] for an inverted element or an assembly failure.
    pub(crate) fn mass_matrix(&self, density: f64) -> Result<SparseColMat<usize, f64>> {
        let mesh = &self.mesh;
        let mut triplets: Vec<Triplet<usize, usize, f64>> =
            Vec::with_capacity(mesh.triangles.len() * 72);
        for t in &mesh.triangles {
            let x: [Vec2; 6] = std::array::from_fn(|k| mesh.nodes[t[k]]);
            let me = element_mass(&x, density, self.material.thickness)?;
            for a in 0..12 {
                let da = &self.dofs[2 * t[a / 2] + a % 2];
                for b in 0..12 {
                    if a % 2 != b % 2 {
                        continue;
                    }
                    let db = &self.dofs[2 * t[b / 2] + b % 2];
                    let m = me[a / 2][b / 2];
                    for &(qa, ca) in &da.terms {
                        for &(qb, cb) in &db.terms {
                            triplets.push(Triplet::new(qa, qb, ca * cb * m));
                        }
                    }
                }
            }
        }
        SparseColMat::<usize, f64>::try_new_from_triplets(self.equations, self.equations, &triplets)
            .map_err(|e| Error::numerical("fem mass assembly", format!("{e:?}")))
    }

    /// Inertia loads of the rigid-body accelerations of the disc frame, reduced to the
    /// equations: `T^T M r_k` for the unit accelerations `r_k` = translation along `x`, along
    /// `y`, and rotation about the frame origin (every node, whatever its constraint), with the
    /// full nodal consistent mass `M` at `density` (kg/m^3). Their products with a mode are the
    /// mode's participation factors (kg^1/2 m, kg^1/2 m^2 for mass-normalised modes). Also
    /// returns the rigid mass (kg) and the polar inertia about the origin (kg m^2) of the mesh.
    ///
    /// # Errors
    /// [`Error::Numerical`] for an inverted element.
    pub(crate) fn rigid_inertia_loads(&self, density: f64) -> Result<([Vec<f64>; 3], f64, f64)> {
        let mesh = &self.mesh;
        let nn = mesh.nodes.len();
        let mut full: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; 2 * nn]);
        let (mut mass, mut polar) = (0.0, 0.0);
        for t in &mesh.triangles {
            let x: [Vec2; 6] = std::array::from_fn(|k| mesh.nodes[t[k]]);
            let me = element_mass(&x, density, self.material.thickness)?;
            for a in 0..6 {
                for b in 0..6 {
                    let m = me[a][b];
                    let xb = x[b];
                    full[0][2 * t[a]] += m;
                    full[1][2 * t[a] + 1] += m;
                    full[2][2 * t[a]] -= m * xb.y;
                    full[2][2 * t[a] + 1] += m * xb.x;
                    mass += m;
                    polar += m * x[a].dot(&xb);
                }
            }
        }
        Ok((
            [
                self.reduce(&full[0]),
                self.reduce(&full[1]),
                self.reduce(&full[2]),
            ],
            mass,
            polar,
        ))
    }

    /// Number of unknowns.
    pub(crate) fn equations(&self) -> usize {
        self.equations
    }

    /// Reduces a nodal load vector (`2 N`, N; `fx, fy` per node) to the equations.
    pub(crate) fn reduce(&self, load: &[f64]) -> Vec<f64> {
        let mut f = vec![0.0; self.equations];
        for (i, &v) in load.iter().enumerate() {
            if v != 0.0 {
                for &(q, c) in &self.dofs[i].terms {
                    f[q] += c * v;
                }
            }
        }
        f
    }

    /// Sparse form of [`FeModel::reduce`] for a load given as `(node dof, value)` pairs.
    pub(crate) fn reduce_sparse(&self, load: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut out: Vec<(usize, f64)> = Vec::new();
        for &(i, v) in load {
            for &(q, c) in &self.dofs[i].terms {
                out.push((q, c * v));
            }
        }
        out.sort_by_key(|p| p.0);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(out.len());
        for (q, v) in out {
            match merged.last_mut() {
                Some(l) if l.0 == q => l.1 += v,
                _ => merged.push((q, v)),
            }
        }
        merged
    }

    /// Solves for reduced loads given as the columns of `rhs` (equations x n), in place.
    pub(crate) fn solve_reduced(&self, rhs: &mut Mat<f64>) {
        self.llt.solve_in_place(rhs.as_mut());
    }

    /// Compliance between reduced loads `C = B K^-1 B^T` ([`Factor::condense`]).
    pub(crate) fn condense(&self, loads: &[Vec<(usize, f64)>]) -> Vec<f64> {
        self.llt.condense(loads)
    }

    /// Node displacements (`2 N`, m) for the nodal load vector `load` (`2 N`, N), with the
    /// prescribed displacements applied.
    pub fn solve(&self, load: &[f64]) -> Vec<f64> {
        let f = self.reduce(load);
        let mut rhs = Mat::<f64>::from_fn(self.equations, 1, |i, _| f[i] + self.lift[i]);
        self.solve_reduced(&mut rhs);
        self.expand(|q| rhs[(q, 0)])
    }

    /// Node displacements from the equation values `x(q)`.
    pub(crate) fn expand(&self, x: impl Fn(usize) -> f64) -> Vec<f64> {
        self.dofs
            .iter()
            .map(|d| d.constant + d.terms.iter().map(|&(q, c)| c * x(q)).sum::<f64>())
            .collect()
    }

    /// Node-averaged stresses of the displacement field `u` (`2 N`, m), Pa.
    pub(crate) fn stresses(&self, u: &[f64]) -> NodalStress {
        let d = self.material.d();
        let n = self.mesh.nodes.len();
        let mut sum = vec![[0.0; 3]; n];
        let mut count = vec![0u32; n];
        for t in &self.mesh.triangles {
            let x: [Vec2; 6] = std::array::from_fn(|k| self.mesh.nodes[t[k]]);
            for (k, &(xi, eta)) in NODE_XI.iter().enumerate() {
                let (g, _) = gradients(&x, xi, eta);
                let (mut ex, mut ey, mut gxy) = (0.0, 0.0, 0.0);
                for a in 0..6 {
                    let (ux, uy) = (u[2 * t[a]], u[2 * t[a] + 1]);
                    ex += g[a][0] * ux;
                    ey += g[a][1] * uy;
                    gxy += g[a][1] * ux + g[a][0] * uy;
                }
                let s = [
                    d[0][0] * ex + d[0][1] * ey,
                    d[1][0] * ex + d[1][1] * ey,
                    d[2][2] * gxy,
                ];
                let i = t[k];
                for c in 0..3 {
                    sum[i][c] += s[c];
                }
                count[i] += 1;
            }
        }
        NodalStress {
            stress: sum
                .iter()
                .zip(&count)
                .map(|(s, &c)| s.map(|v| v / c.max(1) as f64))
                .collect(),
        }
    }
}

/// Consistent nodal loads (`(node dof, N)` pairs) of a traction `traction(x)` (N/m^2, the force
/// per unit area of the boundary; times the thickness gives N/m along the edge) over the
/// boundary edges `edges`, by 8-point Gauss quadrature per edge ([`GAUSS_LEGENDRE8`]).
pub(crate) fn traction_load(
    mesh: &Mesh,
    thickness: f64,
    edges: impl Iterator<Item = usize>,
    traction: impl Fn(&Vec2) -> Option<Vec2>,
) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for e in edges {
        let nd = mesh.boundary[e].nodes;
        let x = [mesh.nodes[nd[0]], mesh.nodes[nd[1]], mesh.nodes[nd[2]]];
        let mut f = [Vec2::zeros(); 3];
        let mut any = false;
        for &(s, w) in &GAUSS_LEGENDRE8 {
            let n = edge_shape(s);
            let dn = edge_shape_derivative(s);
            let p = x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
            let dx = x[0] * dn[0] + x[1] * dn[1] + x[2] * dn[2];
            if let Some(t) = traction(&p) {
                any = true;
                for k in 0..3 {
                    f[k] += t * (n[k] * w * dx.norm() * thickness);
                }
            }
        }
        if any {
            for k in 0..3 {
                out.push((2 * nd[k], f[k].x));
                out.push((2 * nd[k] + 1, f[k].y));
            }
        }
    }
    out
}

/// Scales the nodal loads `load` (`(node dof, N)` pairs) so that their resultant along the
/// unit vector `dir` is `size` (N); unchanged if that resultant is not positive.
pub(crate) fn scale_to_resultant(load: &mut [(usize, f64)], dir: &Vec2, size: f64) {
    let total: f64 = load
        .chunks(2)
        .map(|c| c[0].1 * dir.x + c[1].1 * dir.y)
        .sum();
    if total > 0.0 {
        for l in load.iter_mut() {
            l.1 = l.1 / total * size;
        }
    }
}

/// 8-point Gauss-Legendre rule on `[-1, 1]`: `(point, weight)` (Abramowitz & Stegun,
/// table 25.4), exact to degree 15.
pub(crate) const GAUSS_LEGENDRE8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_2, 0.101_228_536_290_376_3),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_3),
];
