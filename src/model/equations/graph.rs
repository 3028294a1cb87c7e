//! Expressions as one shared graph: every distinct subexpression is one node (hash-consed), so
//! a named intermediate used twice is computed once, and symbolic derivatives reuse the nodes
//! they are built from. The arguments of `max`, `min`, `abs` and `if` become switching
//! functions; each kink is a [`Node::Select`] between two smooth branches.

use std::collections::HashMap;

/// Index of a node in its [`Graph`].
pub type NodeId = u32;

/// A smooth function of one argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func {
    Neg,
    Sin,
    Cos,
    Tan,
    Exp,
    Ln,
    Sqrt,
    Sinh,
    Cosh,
    Tanh,
    Asin,
    Acos,
    Atan,
    /// 0 where its argument is a number, NaN where it is not (NaN or infinite): added to a
    /// kink so that a switching function without a value gives the kink none, rather than
    /// a branch. No session names it.
    Undefined,
}

impl Func {
    /// The function's value.
    #[inline(always)]
    pub fn apply(self, a: f64) -> f64 {
        match self {
            Func::Neg => -a,
            Func::Sin => a.sin(),
            Func::Cos => a.cos(),
            Func::Tan => a.tan(),
            Func::Exp => a.exp(),
            Func::Ln => a.ln(),
            Func::Sqrt => a.sqrt(),
            Func::Sinh => a.sinh(),
            Func::Cosh => a.cosh(),
            Func::Tanh => a.tanh(),
            Func::Asin => a.asin(),
            Func::Acos => a.acos(),
            Func::Atan => a.atan(),
            Func::Undefined => {
                if a.is_finite() {
                    0.0
                } else {
                    f64::NAN
                }
            }
        }
    }

    /// The function a session names, if any.
    pub fn named(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "exp" => Func::Exp,
            "ln" | "log" => Func::Ln,
            "sqrt" => Func::Sqrt,
            "sinh" => Func::Sinh,
            "cosh" => Func::Cosh,
            "tanh" => Func::Tanh,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            _ => return None,
        })
    }
}

/// A smooth function of two arguments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Op2 {
    Add,
    Sub,
    Mul,
    Div,
    /// a^b for any real b.
    Pow,
}

impl Op2 {
    #[inline(always)]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Op2::Add => a + b,
            Op2::Sub => a - b,
            Op2::Mul => a * b,
            Op2::Div => a / b,
            Op2::Pow => a.powf(b),
        }
    }
}

/// One node of the graph.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Node {
    Const(f64),
    Time,
    State(u8),
    Param(u16),
    Un(Func, NodeId),
    Bin(Op2, NodeId, NodeId),
    /// a^n for a small integer n.
    Powi(NodeId, i32),
    /// The first branch where switch `k` is on, else the second.
    Select(u8, NodeId, NodeId),
}

/// A switching function: the kink it stands for is on its first branch where the value is
/// positive (or zero, when `strict` is false).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switch {
    pub value: NodeId,
    pub strict: bool,
    /// Whether every kink of this switch has equal branches where its value is zero (those
    /// of `max`, `min` and `abs`), so that what depends on it is continuous across it.
    pub continuous: bool,
}

impl Switch {
    /// Whether a switching value `s` puts the kink on its first branch.
    #[inline(always)]
    pub fn on(&self, s: f64) -> bool {
        if self.strict { s > 0.0 } else { s >= 0.0 }
    }
}

/// What a derivative is taken with respect to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Wrt {
    State(u8),
    Time,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Const(u64),
    Time,
    State(u8),
    Param(u16),
    Un(Func, NodeId),
    Bin(Op2, NodeId, NodeId),
    Powi(NodeId, i32),
    Select(u8, NodeId, NodeId),
}

/// Most switching functions a model may have (one bit each of a mode word).
pub const MAX_SWITCHES: usize = 64;

/// The graph of a model's expressions.
#[derive(Debug, Clone, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    /// Whether each node depends on the time or a state (else the parameters fix it).
    varies: Vec<bool>,
    index: HashMap<Key, NodeId>,
    pub switches: Vec<Switch>,
    derivatives: HashMap<(NodeId, Wrt), NodeId>,
}

impl Graph {
    pub fn node(&self, id: NodeId) -> Node {
        self.nodes[id as usize]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    fn intern(&mut self, node: Node) -> NodeId {
        let key = match node {
            Node::Const(v) => Key::Const(if v == 0.0 { 0 } else { v.to_bits() }),
            Node::Time => Key::Time,
            Node::State(i) => Key::State(i),
            Node::Param(i) => Key::Param(i),
            Node::Un(f, a) => Key::Un(f, a),
            Node::Bin(op, a, b) => Key::Bin(op, a, b),
            Node::Powi(a, n) => Key::Powi(a, n),
            Node::Select(k, a, b) => Key::Select(k, a, b),
        };
        if let Some(&id) = self.index.get(&key) {
            return id;
        }
        let id = self.nodes.len() as NodeId;
        let varies = match node {
            Node::Const(_) | Node::Param(_) => false,
            Node::Time | Node::State(_) => true,
            Node::Un(_, a) | Node::Powi(a, _) => self.varies[a as usize],
            Node::Bin(_, a, b) => self.varies[a as usize] || self.varies[b as usize],
            Node::Select(k, a, b) => {
                self.varies[a as usize]
                    || self.varies[b as usize]
                    || self.varies[self.switches[k as usize].value as usize]
            }
        };
        self.nodes.push(node);
        self.varies.push(varies);
        self.index.insert(key, id);
        id
    }

    /// The value of node `id` if it is a constant.
    pub fn constant(&self, id: NodeId) -> Option<f64> {
        match self.nodes[id as usize] {
            Node::Const(v) => Some(v),
            _ => None,
        }
    }

    pub fn num(&mut self, v: f64) -> NodeId {
        self.intern(Node::Const(v))
    }

    pub fn time(&mut self) -> NodeId {
        self.intern(Node::Time)
    }

    pub fn state(&mut self, i: usize) -> NodeId {
        self.intern(Node::State(i as u8))
    }

    pub fn param(&mut self, i: usize) -> NodeId {
        self.intern(Node::Param(i as u16))
    }

    /// f(a), folded when a is a constant.
    pub fn un(&mut self, f: Func, a: NodeId) -> NodeId {
        if let Some(v) = self.constant(a) {
            return self.num(f.apply(v));
        }
        if let (Func::Neg, Node::Un(Func::Neg, inner)) = (f, self.node(a)) {
            return inner;
        }
        self.intern(Node::Un(f, a))
    }

    pub fn neg(&mut self, a: NodeId) -> NodeId {
        self.un(Func::Neg, a)
    }

    /// a op b, with the identities of 0 and 1 applied and constants folded.
    pub fn bin(&mut self, op: Op2, a: NodeId, b: NodeId) -> NodeId {
        let (ca, cb) = (self.constant(a), self.constant(b));
        if let (Some(x), Some(y)) = (ca, cb) {
            return self.num(op.apply(x, y));
        }
        match (op, ca, cb) {
            (Op2::Add, Some(0.0), _) => b,
            (Op2::Add | Op2::Sub, _, Some(0.0)) => a,
            (Op2::Sub, Some(0.0), _) => self.neg(b),
            (Op2::Mul, Some(0.0), _) | (Op2::Mul, _, Some(0.0)) => self.num(0.0),
            (Op2::Mul, Some(1.0), _) => b,
            (Op2::Mul | Op2::Div, _, Some(1.0)) => a,
            (Op2::Mul, Some(-1.0), _) => self.neg(b),
            (Op2::Mul | Op2::Div, _, Some(-1.0)) => self.neg(a),
            (Op2::Div, Some(0.0), _) => self.num(0.0),
            (Op2::Pow, _, Some(n)) if n == n.round() && n.abs() <= 16.0 => self.powi(a, n as i32),
            // a varying quotient of a divisor the parameters fix: a product with the
            // reciprocal, computed once per parameter set (a division off the field's chain)
            (Op2::Div, _, _) if self.varies[a as usize] && !self.varies[b as usize] => {
                let one = self.num(1.0);
                let reciprocal = self.div(one, b);
                self.mul(a, reciprocal)
            }
            _ => self.intern(Node::Bin(op, a, b)),
        }
    }

    pub fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(Op2::Add, a, b)
    }

    pub fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(Op2::Sub, a, b)
    }

    pub fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(Op2::Mul, a, b)
    }

    pub fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(Op2::Div, a, b)
    }

    /// a^n for an integer n: small powers as products (a multiplication is cheaper than a
    /// call), small negative ones as powers of 1/a (one division shared by all).
    pub fn powi(&mut self, a: NodeId, n: i32) -> NodeId {
        match n {
            0 => self.num(1.0),
            1 => a,
            2 => self.mul(a, a),
            3 => {
                let sq = self.mul(a, a);
                self.mul(sq, a)
            }
            4 => {
                let sq = self.mul(a, a);
                self.mul(sq, sq)
            }
            -4..=-1 => {
                // (1/a)^n: one division for every negative power of a
                let one = self.num(1.0);
                let reciprocal = self.div(one, a);
                self.powi(reciprocal, -n)
            }
            _ => match self.constant(a) {
                Some(v) => self.num(v.powi(n)),
                None => self.intern(Node::Powi(a, n)),
            },
        }
    }

    /// A new switching function `value`, and the node that is `on` where it is on and `off`
    /// elsewhere; `continuous` where `on` and `off` are equal wherever `value` is zero.
    /// Fails past [`MAX_SWITCHES`].
    pub fn kink(
        &mut self,
        value: NodeId,
        strict: bool,
        continuous: bool,
        on: NodeId,
        off: NodeId,
    ) -> Result<NodeId, usize> {
        if on == off {
            return Ok(on);
        }
        if let Some(v) = self.constant(value) {
            let s = Switch {
                value,
                strict,
                continuous,
            };
            return Ok(if s.on(v) { on } else { off });
        }
        let k = match self
            .switches
            .iter()
            .position(|s| s.value == value && s.strict == strict)
        {
            Some(k) => {
                self.switches[k].continuous &= continuous;
                k
            }
            None if self.switches.len() == MAX_SWITCHES => return Err(MAX_SWITCHES),
            None => {
                self.switches.push(Switch {
                    value,
                    strict,
                    continuous,
                });
                self.switches.len() - 1
            }
        };
        // NaN where the switching value is not a number (`max(sqrt(x - 5), 0)` below 5), not
        // the branch a NaN comparison would pick
        let kink = self.select(k as u8, on, off);
        let undefined = self.un(Func::Undefined, value);
        Ok(self.add(kink, undefined))
    }

    fn select(&mut self, k: u8, on: NodeId, off: NodeId) -> NodeId {
        if on == off {
            on
        } else {
            self.intern(Node::Select(k, on, off))
        }
    }

    /// ∂node/∂wrt, built in the graph (memoised). Within each smooth piece the derivative of
    /// a kink is the derivative of its branch.
    pub fn derivative(&mut self, id: NodeId, wrt: Wrt) -> NodeId {
        if let Some(&d) = self.derivatives.get(&(id, wrt)) {
            return d;
        }
        let d = match self.node(id) {
            Node::Const(_) | Node::Param(_) => self.num(0.0),
            Node::Time => self.num(if wrt == Wrt::Time { 1.0 } else { 0.0 }),
            Node::State(i) => self.num(if wrt == Wrt::State(i) { 1.0 } else { 0.0 }),
            Node::Un(f, a) => {
                let da = self.derivative(a, wrt);
                if self.constant(da) == Some(0.0) {
                    da
                } else {
                    let outer = self.outer_derivative(f, a, id);
                    self.mul(outer, da)
                }
            }
            Node::Bin(op, a, b) => {
                let (da, db) = (self.derivative(a, wrt), self.derivative(b, wrt));
                match op {
                    Op2::Add => self.add(da, db),
                    Op2::Sub => self.sub(da, db),
                    Op2::Mul => {
                        let (x, y) = (self.mul(da, b), self.mul(a, db));
                        self.add(x, y)
                    }
                    // d(a/b) = (da − (a/b)·db)/b
                    Op2::Div => {
                        let q = self.mul(id, db);
                        let num = self.sub(da, q);
                        self.div(num, b)
                    }
                    // d(a^b) = a^b·(db·ln a + b·da/a)
                    Op2::Pow => {
                        let ln_a = self.un(Func::Ln, a);
                        let x = self.mul(db, ln_a);
                        let r = self.div(da, a);
                        let y = self.mul(b, r);
                        let s = self.add(x, y);
                        self.mul(id, s)
                    }
                }
            }
            Node::Powi(a, n) => {
                let da = self.derivative(a, wrt);
                let lower = self.powi(a, n - 1);
                let n = self.num(n as f64);
                let outer = self.mul(n, lower);
                self.mul(outer, da)
            }
            Node::Select(k, a, b) => {
                let (da, db) = (self.derivative(a, wrt), self.derivative(b, wrt));
                self.select(k, da, db)
            }
        };
        self.derivatives.insert((id, wrt), d);
        d
    }

    /// f′(a), where `id` is the node f(a) itself.
    fn outer_derivative(&mut self, f: Func, a: NodeId, id: NodeId) -> NodeId {
        let one = self.num(1.0);
        match f {
            Func::Neg => self.num(-1.0),
            Func::Sin => self.un(Func::Cos, a),
            Func::Cos => {
                let s = self.un(Func::Sin, a);
                self.neg(s)
            }
            Func::Tan => {
                let sq = self.powi(id, 2);
                self.add(one, sq)
            }
            Func::Exp => id,
            Func::Ln => self.div(one, a),
            Func::Sqrt => {
                let two = self.num(2.0);
                let d = self.mul(two, id);
                self.div(one, d)
            }
            Func::Sinh => self.un(Func::Cosh, a),
            Func::Cosh => self.un(Func::Sinh, a),
            Func::Tanh => {
                let sq = self.powi(id, 2);
                self.sub(one, sq)
            }
            Func::Asin | Func::Acos => {
                let sq = self.powi(a, 2);
                let r = self.sub(one, sq);
                let root = self.un(Func::Sqrt, r);
                let inv = self.div(one, root);
                if f == Func::Asin { inv } else { self.neg(inv) }
            }
            Func::Atan => {
                let sq = self.powi(a, 2);
                let d = self.add(one, sq);
                self.div(one, d)
            }
            Func::Undefined => self.num(0.0),
        }
    }

    /// Each state variable's node: (state index, node).
    pub fn states(&self) -> Vec<(u8, NodeId)> {
        (0..self.len() as NodeId)
            .filter_map(|id| match self.node(id) {
                Node::State(i) => Some((i, id)),
                _ => None,
            })
            .collect()
    }

    /// Whether a node depends on the time or a state (else it is fixed by the parameters).
    pub fn varying(&self) -> &[bool] {
        &self.varies
    }

    /// Whether every node repeats with the forcing period 2π/ω, ω being parameter `omega`:
    /// the time enters only as k·ω·t plus a fixed phase (k a whole number) inside sin, cos or
    /// tan, and no `roots` (what the model's users read) is t or such a phase itself. Then
    /// one period's values of the time-only nodes serve every period. A model using t
    /// otherwise (`exp(-t)`, `cos(omega*t/2)`, `t*x`) is not taken to be periodic.
    pub fn periodic_in_time(&self, omega: u16, roots: &[NodeId]) -> bool {
        /// What a node is as a function of time.
        #[derive(Clone, Copy, PartialEq)]
        enum Kind {
            /// Constant in time and fixed by the parameters, or periodic.
            Repeating,
            /// k·ω for a whole k ≠ 0 (fixed, and a valid factor of t).
            WholeOmega,
            Time,
            /// k·ω·t + a fixed phase: periodic only inside sin, cos or tan.
            Phase,
        }
        use Kind::*;
        let varying = self.varying();
        let whole = |id: NodeId| matches!(self.node(id), Node::Const(v) if v == v.round() && v != 0.0 && v.abs() < 1e15);
        let mut kind: Vec<Kind> = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let k = |i: NodeId| kind[i as usize];
            let fixed = |i: NodeId| !varying[i as usize];
            let this = match *node {
                Node::Time => Time,
                Node::Param(p) if p == omega => WholeOmega,
                Node::Un(Func::Neg, a) if matches!(k(a), WholeOmega | Phase) => k(a),
                Node::Un(Func::Sin | Func::Cos | Func::Tan, a) if k(a) == Phase => Repeating,
                Node::Bin(Op2::Mul, a, b) => match (k(a), k(b)) {
                    (WholeOmega, Time) | (Time, WholeOmega) => Phase,
                    (WholeOmega, _) if whole(b) => WholeOmega,
                    (_, WholeOmega) if whole(a) => WholeOmega,
                    (Phase, _) if whole(b) => Phase,
                    (_, Phase) if whole(a) => Phase,
                    _ => Repeating,
                },
                Node::Bin(Op2::Add | Op2::Sub, a, b) => match (k(a), k(b)) {
                    (Phase, Phase) => Phase,
                    (Phase, _) if fixed(b) => Phase,
                    (_, Phase) if fixed(a) => Phase,
                    _ => Repeating,
                },
                _ => Repeating,
            };
            // any other use of t or of a phase breaks the period
            let arguments: &[NodeId] = match *node {
                Node::Un(_, a) | Node::Powi(a, _) => &[a],
                Node::Bin(_, a, b) => &[a, b],
                Node::Select(s, a, b) => &[a, b, self.switches[s as usize].value],
                _ => &[],
            };
            let trig_of_phase =
                matches!(*node, Node::Un(Func::Sin | Func::Cos | Func::Tan, a) if k(a) == Phase);
            let consumed = matches!(this, Phase | WholeOmega) || trig_of_phase;
            if !consumed && arguments.iter().any(|&a| matches!(k(a), Time | Phase)) {
                return false;
            }
            kind.push(this);
        }
        roots
            .iter()
            .all(|&r| !matches!(kind[r as usize], Time | Phase))
    }
}
