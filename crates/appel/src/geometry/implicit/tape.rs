//! A formula compiled to a flat tape: a list of operations in evaluation order, operation `i` writing
//! slot `i` and reading only earlier slots. Constant subexpressions are folded and repeated
//! subexpressions shared (hash-consing), so `x^2` written three times is computed once.
//!
//! The same tape is evaluated in any [`Num`]: f64 values, intervals and dual numbers.

use super::num::Num;
use super::parse::{Ast, BinOp, Func, Node};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    Var(u8),
    Const(f64),
    Bin(BinOp, u32, u32),
    Neg(u32),
    Pow(u32, i32),
    Call(Func, u32),
}

/// Hashable form of an [`Op`] (the constant by its bits), for sharing repeated subexpressions.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Var(u8),
    Const(u64),
    Bin(BinOp, u32, u32),
    Neg(u32),
    Pow(u32, i32),
    Call(Func, u32),
}

impl From<Op> for Key {
    fn from(op: Op) -> Self {
        match op {
            Op::Var(v) => Key::Var(v),
            Op::Const(c) => Key::Const(c.to_bits()),
            Op::Bin(o, a, b) => Key::Bin(o, a, b),
            Op::Neg(a) => Key::Neg(a),
            Op::Pow(a, n) => Key::Pow(a, n),
            Op::Call(f, a) => Key::Call(f, a),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    pub ops: Vec<Op>,
}

pub fn apply_bin<T: Num>(op: BinOp, a: T, b: T) -> T {
    match op {
        BinOp::Add => a.add(b),
        BinOp::Sub => a.sub(b),
        BinOp::Mul => a.mul(b),
        BinOp::Div => a.div(b),
        BinOp::Min => a.min(b),
        BinOp::Max => a.max(b),
    }
}

pub fn apply_func<T: Num>(f: Func, a: T) -> T {
    match f {
        Func::Sqrt => a.sqrt(),
        Func::Abs => a.abs(),
        Func::Sin => a.sin(),
        Func::Cos => a.cos(),
        Func::Exp => a.exp(),
    }
}

impl Tape {
    pub fn compile(ast: &Ast) -> Tape {
        let mut ops: Vec<Op> = Vec::new();
        let mut seen: HashMap<Key, u32> = HashMap::new();
        // Slot of each AST node; the arena is in post-order so children are always mapped already.
        let mut slot: Vec<u32> = Vec::with_capacity(ast.nodes.len());
        for node in &ast.nodes[..=ast.root as usize] {
            let s = |i: &u32| slot[*i as usize];
            let op = match *node {
                Node::Num(v) => Op::Const(v),
                Node::Var(v) => Op::Var(v),
                Node::Neg(a) => Op::Neg(s(&a)),
                Node::Bin(o, a, b) => Op::Bin(o, s(&a), s(&b)),
                Node::Pow(a, n) => Op::Pow(s(&a), n),
                Node::Call(f, a) => Op::Call(f, s(&a)),
            };
            let op = fold(&ops, op);
            let op = strength_reduce(&mut ops, &mut seen, op);
            let id = *seen.entry(Key::from(op)).or_insert_with(|| {
                ops.push(op);
                ops.len() as u32 - 1
            });
            slot.push(id);
        }
        // Drop what folding left unused. Everything reachable lies at or before the root's slot, so
        // after compaction the root is the last op.
        let root = slot[ast.root as usize] as usize;
        let mut live = vec![false; root + 1];
        live[root] = true;
        for i in (0..=root).rev() {
            if live[i] {
                match ops[i] {
                    Op::Bin(_, a, b) => {
                        live[a as usize] = true;
                        live[b as usize] = true;
                    }
                    Op::Neg(a) | Op::Pow(a, _) | Op::Call(_, a) => live[a as usize] = true,
                    Op::Var(_) | Op::Const(_) => {}
                }
            }
        }
        let mut new_index = vec![0u32; root + 1];
        let mut kept = Vec::new();
        for i in 0..=root {
            if live[i] {
                let m = |j: u32| new_index[j as usize];
                let op = match ops[i] {
                    Op::Bin(o, a, b) => Op::Bin(o, m(a), m(b)),
                    Op::Neg(a) => Op::Neg(m(a)),
                    Op::Pow(a, n) => Op::Pow(m(a), n),
                    Op::Call(f, a) => Op::Call(f, m(a)),
                    op => op,
                };
                new_index[i] = kept.len() as u32;
                kept.push(op);
            }
        }
        let ops = kept;
        Tape { ops }
    }

    pub fn len(&self) -> usize {
        self.ops.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Evaluates the tape at `xyz`, using `slots` as scratch space (resized as needed).
    #[inline]
    pub fn eval<T: Num>(&self, xyz: [T; 3], slots: &mut Vec<T>) -> T {
        slots.clear();
        for op in &self.ops {
            let g = |i: u32| slots[i as usize];
            let v = match *op {
                Op::Var(v) => xyz[v as usize],
                Op::Const(c) => T::constant(c),
                Op::Bin(o, a, b) => apply_bin(o, g(a), g(b)),
                Op::Neg(a) => g(a).neg(),
                Op::Pow(a, n) => g(a).powi(n),
                Op::Call(f, a) => apply_func(f, g(a)),
            };
            slots.push(v);
        }
        slots[slots.len() - 1]
    }

    pub fn eval_f64(&self, p: [f64; 3]) -> f64 {
        self.eval(p, &mut Vec::with_capacity(self.len()))
    }
}

/// Replaces an operation on constants by its value.
fn fold(ops: &[Op], op: Op) -> Op {
    let c = |i: u32| match ops[i as usize] {
        Op::Const(v) => Some(v),
        _ => None,
    };
    let v = match op {
        Op::Bin(o, a, b) => c(a).zip(c(b)).map(|(a, b)| apply_bin(o, a, b)),
        Op::Neg(a) => c(a).map(|a| -a),
        Op::Pow(a, n) => c(a).map(|a| Num::powi(a, n)),
        Op::Call(f, a) => c(a).map(|a| apply_func(f, a)),
        _ => None,
    };
    if let Some(v) = v {
        return Op::Const(v);
    }
    op
}

/// Division by a constant becomes multiplication by its reciprocal (interval division is several
/// times slower than multiplication). This changes the f64 value by at most an ulp, and since every
/// evaluator runs the same tape they still agree with each other exactly.
fn strength_reduce(ops: &mut Vec<Op>, seen: &mut HashMap<Key, u32>, op: Op) -> Op {
    if let Op::Bin(BinOp::Div, a, b) = op {
        if let Op::Const(c) = ops[b as usize] {
            let r = 1.0 / c;
            if c != 0.0 && r.is_finite() && r != 0.0 {
                let k = Op::Const(r);
                let id = *seen.entry(Key::from(k)).or_insert_with(|| {
                    ops.push(k);
                    ops.len() as u32 - 1
                });
                return Op::Bin(BinOp::Mul, a, id);
            }
        }
    }
    op
}

#[cfg(test)]
mod tests {
    use super::super::parse::parse;
    use super::*;

    fn tape(s: &str) -> Tape {
        Tape::compile(&parse(s).unwrap())
    }

    #[test]
    fn evaluates_like_the_formula() {
        let t = tape(
            "x^2 + 2*y - z/4 + sqrt(abs(-9)) + min(x, y) * max(1, 2) - exp(0) + sin(0) + cos(0)",
        );
        let (x, y, z) = (1.5f64, -0.5f64, 2.0f64);
        let expect = x * x + 2.0 * y - z / 4.0 + 3.0 + x.min(y) * 2.0 - 1.0 + 0.0 + 1.0;
        assert!((t.eval_f64([x, y, z]) - expect).abs() < 1e-12);
        assert_eq!(tape("x^-2").eval_f64([2.0, 0.0, 0.0]), 0.25);
        assert_eq!(tape("-2^2").eval_f64([0.0; 3]), -4.0);
        assert_eq!(tape("2^3^2").eval_f64([0.0; 3]), 512.0);
        assert_eq!(tape("x/4").eval_f64([3.0, 0.0, 0.0]), 0.75);
        assert!(tape("x/0").eval_f64([3.0, 0.0, 0.0]).is_infinite());
    }

    #[test]
    fn constants_fold_and_repeats_are_shared() {
        let t = tape("(1 + 2) * 3");
        assert_eq!(t.ops, vec![Op::Const(9.0)]);
        let t = tape("x^2 + x^2 + x^2");
        // x, x^2, x^2 + x^2, (..) + x^2.
        assert_eq!(t.len(), 4);
        assert_eq!(tape("2 + 1 + 0").ops, vec![Op::Const(3.0)]);
        assert_eq!(tape("x").eval_f64([3.0, 0.0, 0.0]), 3.0);
    }
}
