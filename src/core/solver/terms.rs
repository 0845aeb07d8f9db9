//! What the solver is given besides the fabric: the terms that act on single nodes (contact,
//! friction, the blank holder, dead loads) and the prescribed displacements.
//!
//! The residual convention is `r = f_int − f_ext`: a term adds the force it takes from a node.

/// The derivative of the nodal terms' force at one node with respect to that node's position,
/// `∂r_i/∂x_i`, in two parts: `spd`, symmetric positive semi-definite, joins the tangent that
/// is factorized; `rest` (any 3×3: friction that follows the normal force, curvature) is taken
/// by the Krylov iterations on each Newton correction. Their sum is the exact derivative.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodeBlock {
    pub spd: [[f64; 3]; 3],
    pub rest: [[f64; 3]; 3],
}

impl NodeBlock {
    /// The whole derivative, `spd + rest`.
    pub fn total(&self) -> [[f64; 3]; 3] {
        let mut m = self.spd;
        for a in 0..3 {
            for b in 0..3 {
                m[a][b] += self.rest[a][b];
            }
        }
        m
    }

    pub fn is_zero(&self) -> bool {
        self.rest.iter().flatten().all(|v| *v == 0.0)
            && self.spd.iter().flatten().all(|v| *v == 0.0)
    }
}

/// A tangent term that couples many nodes through one unknown condensed out (the holder
/// plate's height): `diag(u²)/total − u uᵀ/total` on the nodes' z dofs, beyond their blocks
/// (whose z diagonal holds `u − u²/total`), so that the whole is `diag(u) − u uᵀ/total`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RankOne {
    /// Each node and its `u` (N/mm).
    pub nodes: Vec<(usize, f64)>,
    /// `Σ u`, N/mm.
    pub total: f64,
}

/// A node's own 3×3 block of the factorized tangent, `K_ii` (N/mm), over its free dofs: the
/// rows and columns of a prescribed dof (a symmetry plane's normal, a clamp) are zero and
/// `free` says which they are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OwnStiffness {
    pub k: [[f64; 3]; 3],
    pub free: [bool; 3],
}

/// Node `i`'s [`OwnStiffness`] (`None` when all its dofs are prescribed): what
/// [`NodalTerms::reshape`] holds the rest of a node's load to.
pub type NodeStiffness<'a> = &'a dyn Fn(usize) -> Option<OwnStiffness>;

/// What [`NodalTerms::add`] returns besides the forces.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodalSums {
    /// The norm over nodes of each node's largest single force, N (forces that cancel each
    /// other at a node still count): the load scale of the convergence test.
    pub scale: f64,
    /// The terms' potential at `x`, N·mm, with the non-conservative parts (friction's normal
    /// force and direction, the holder's weights) taken at `x` itself.
    pub energy: f64,
    /// The same potential with those parts frozen where [`NodalTerms::freeze`] was last
    /// called: the line search's merit along a Newton correction, whose gradient at the frozen
    /// point is the residual there.
    pub energy_frozen: f64,
}

/// Node-local terms added to the residual and its derivative.
pub trait NodalTerms: Sync {
    /// Called at the start of each load step attempt, from the converged state `x` at
    /// `lambda_start` towards `lambda`.
    fn begin_step(&mut self, _lambda_start: f64, _lambda: f64, _x: &[[f64; 3]]) {}
    /// Moves predicted positions at `lambda` so that the nodes that touched a tool at the step's
    /// start touch it again, and none starts inside a tool; with `keep_slide`, a node that slid
    /// on a tool at rest keeps the distance it slid in the prediction.
    fn project(&self, _lambda: f64, _x: &mut [[f64; 3]], _keep_slide: bool) {}
    /// For each node a tool touched at the step's start (within its eased gap), that tool's
    /// translation along z from the step's start to `lambda`, mm (0 for a tool at rest; a node
    /// touching one at rest and one moving is held by the one at rest); `None` for the others.
    /// Empty when no term touches.
    fn carried_at_start(&self, _lambda: f64) -> Vec<Option<f64>> {
        Vec::new()
    }
    /// Moves a trial state `x` of the line search (from the base `x_base`) so that no node that
    /// a tool did not press at the base starts deep inside one: such a node has no contact
    /// stiffness in the correction, which may throw it far into the tool. It is put on the
    /// tool's surface, where the next correction sees the contact.
    fn project_trial(&self, _lambda: f64, _x_base: &[[f64; 3]], _x: &mut [[f64; 3]]) {}
    /// Puts back into a Newton correction `du` (per node, mm, from the state `x`) what its
    /// linear model of these terms misses at single nodes, each node's share moved to where
    /// its own balance lies with the rest of the correction held. Returns whether any node's
    /// share moved.
    fn reshape(
        &self,
        _lambda: f64,
        _x: &[[f64; 3]],
        _du: &mut [[f64; 3]],
        _stiffness: NodeStiffness,
    ) -> bool {
        false
    }
    /// Takes lagged quantities from the converged state `x` of a step, for terms that lag them
    /// (the step is then solved again, to a fixed point). `false` when nothing is lagged.
    fn relag(&mut self, _lambda: f64, _x: &[[f64; 3]]) -> bool {
        false
    }
    /// Freezes the non-conservative parts at `x` for [`NodalSums::energy_frozen`].
    fn freeze(&mut self, _lambda: f64, _x: &[[f64; 3]]) {}
    /// Adds the forces to `r` (`3·node + m`) and, when `blocks` is given, each node's
    /// derivative. `None` when the configuration is inadmissible (the line search then
    /// shortens the correction).
    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        blocks: Option<&mut [NodeBlock]>,
    ) -> Option<NodalSums>;
    /// The coupling term of the last [`NodalTerms::add`] at `x` (`None`: none), applied by the
    /// Krylov solve beside the blocks' `rest`.
    fn coupling(&self, _x: &[[f64; 3]]) -> Option<RankOne> {
        None
    }
    /// Called when a step is accepted, with its converged state.
    fn end_step(&mut self, _lambda: f64, _x: &[[f64; 3]]) {}
}

/// No nodal terms.
pub struct NoNodalTerms;

impl NodalTerms for NoNodalTerms {
    fn add(
        &self,
        _: f64,
        _: &[[f64; 3]],
        _: &mut [f64],
        _: Option<&mut [NodeBlock]>,
    ) -> Option<NodalSums> {
        Some(NodalSums::default())
    }
}

/// The prescribed displacements: which dofs (`3·node + component`) and their values along the
/// load path `λ ∈ [0, 1]`.
pub trait Prescribed: Sync {
    fn dofs(&self) -> &[usize];
    /// `out[i]` receives the displacement of `dofs()[i]` at `λ`.
    fn values(&self, lambda: f64, out: &mut [f64]);
}

/// Prescribed displacements proportional to the load factor: `u = λ ū`.
#[derive(Clone, Debug, Default)]
pub struct LinearPrescribed {
    pub dofs: Vec<usize>,
    pub at_full_load: Vec<f64>,
}

impl Prescribed for LinearPrescribed {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(&self.at_full_load) {
            *o = lambda * v;
        }
    }
}
