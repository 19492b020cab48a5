//! The formula language of implicit surfaces: a lexer and a recursive-descent parser producing a flat
//! AST (`docs/implicit.md` has the grammar).
//!
//! The AST is an arena in post-order: every node's children have smaller indices than the node, so the
//! compiler walks it with a plain loop and dropping it never recurses. The parser only recurses on
//! nesting (parentheses, unary signs, powers, calls), and that depth is capped, so no input string can
//! overflow the stack; binary chains (`x+x+...+x`) are built iteratively.

use std::fmt;

/// Nesting deeper than this is rejected (it is far beyond any sensible formula).
pub const MAX_DEPTH: usize = 200;
/// The largest exponent magnitude accepted in `x^n`.
pub const MAX_EXPONENT: i32 = 1024;

/// A formula that does not parse: the 1-based column (in characters) and what was wrong there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormulaError {
    pub column: usize,
    pub message: String,
}

impl fmt::Display for FormulaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "column {} of the formula: {}", self.column, self.message)
    }
}

impl std::error::Error for FormulaError {}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Min,
    Max,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Sqrt,
    Abs,
    Sin,
    Cos,
    Exp,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    Num(f64),
    /// 0, 1, 2 for x, y, z.
    Var(u8),
    Neg(u32),
    Bin(BinOp, u32, u32),
    Pow(u32, i32),
    Call(Func, u32),
}

/// A parsed formula: `nodes[root]` is the whole expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Ast {
    pub nodes: Vec<Node>,
    pub root: u32,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Ident(String),
    Sym(char),
    End,
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Num(v) => write!(f, "number `{v}`"),
            Tok::Ident(s) => write!(f, "`{s}`"),
            Tok::Sym(c) => write!(f, "`{c}`"),
            Tok::End => write!(f, "end of formula"),
        }
    }
}

fn err<T>(column: usize, message: impl Into<String>) -> Result<T, FormulaError> {
    Err(FormulaError {
        column,
        message: message.into(),
    })
}

/// Splits the formula into tokens, each with its 1-based character column.
fn lex(src: &str) -> Result<Vec<(Tok, usize)>, FormulaError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent only if digits follow (`2e` is the number 2 and then a name).
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => out.push((Tok::Num(v), col)),
                Ok(_) => return err(col, format!("number `{text}` is too large")),
                Err(_) => return err(col, format!("malformed number `{text}`")),
            }
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Tok::Ident(chars[start..i].iter().collect()), col));
        } else if "+-*/^(),".contains(c) {
            out.push((Tok::Sym(c), col));
            i += 1;
        } else {
            return err(col, format!("unexpected character `{c}`"));
        }
    }
    out.push((Tok::End, chars.len() + 1));
    Ok(out)
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    pos: usize,
    nodes: Vec<Node>,
    depth: usize,
}

const FUNCTIONS: &str = "sqrt, abs, sin, cos, exp, min, max";

impl Parser {
    fn peek(&self) -> &Tok {
        &self.toks[self.pos].0
    }

    fn col(&self) -> usize {
        self.toks[self.pos].1
    }

    fn push(&mut self, n: Node) -> u32 {
        self.nodes.push(n);
        self.nodes.len() as u32 - 1
    }

    fn eat(&mut self, c: char) -> bool {
        if *self.peek() == Tok::Sym(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: char, what: &str) -> Result<(), FormulaError> {
        if self.eat(c) {
            Ok(())
        } else {
            err(
                self.col(),
                format!("expected `{c}` {what}, found {}", self.peek()),
            )
        }
    }

    fn nest<T>(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<T, FormulaError>,
    ) -> Result<T, FormulaError> {
        if self.depth >= MAX_DEPTH {
            return err(
                self.col(),
                format!("the formula nests more than {MAX_DEPTH} levels deep"),
            );
        }
        self.depth += 1;
        let r = f(self);
        self.depth -= 1;
        r
    }

    /// expr := term (('+' | '-') term)*
    fn expr(&mut self) -> Result<u32, FormulaError> {
        let mut lhs = self.term()?;
        loop {
            let op = match self.peek() {
                Tok::Sym('+') => BinOp::Add,
                Tok::Sym('-') => BinOp::Sub,
                _ => return Ok(lhs),
            };
            self.pos += 1;
            let rhs = self.term()?;
            lhs = self.push(Node::Bin(op, lhs, rhs));
        }
    }

    /// term := unary (('*' | '/') unary)*
    fn term(&mut self) -> Result<u32, FormulaError> {
        let mut lhs = self.unary()?;
        loop {
            let op = match self.peek() {
                Tok::Sym('*') => BinOp::Mul,
                Tok::Sym('/') => BinOp::Div,
                _ => return Ok(lhs),
            };
            self.pos += 1;
            let rhs = self.unary()?;
            lhs = self.push(Node::Bin(op, lhs, rhs));
        }
    }

    /// unary := ('-' | '+') unary | power. `-x^2` is `-(x^2)`, as in mathematics.
    fn unary(&mut self) -> Result<u32, FormulaError> {
        self.nest(|p| {
            if p.eat('-') {
                let a = p.unary()?;
                Ok(p.push(Node::Neg(a)))
            } else if p.eat('+') {
                p.unary()
            } else {
                p.power()
            }
        })
    }

    /// power := primary ('^' unary)?, the exponent an integer constant; right-associative.
    fn power(&mut self) -> Result<u32, FormulaError> {
        let base = self.primary()?;
        if !self.eat('^') {
            return Ok(base);
        }
        let col = self.col();
        let e = self.unary()?;
        let value = const_value(&self.nodes, e);
        match value {
            Some(v) if v.fract() == 0.0 && v.abs() <= MAX_EXPONENT as f64 => {
                Ok(self.push(Node::Pow(base, v as i32)))
            }
            _ => err(
                col,
                format!(
                    "the exponent must be an integer constant between -{MAX_EXPONENT} and \
                     {MAX_EXPONENT} (like x^2 or x^-1); for other powers use exp or sqrt"
                ),
            ),
        }
    }

    /// primary := number | variable | function '(' expr (',' expr)? ')' | '(' expr ')'
    fn primary(&mut self) -> Result<u32, FormulaError> {
        let col = self.col();
        match self.peek().clone() {
            Tok::Num(v) => {
                self.pos += 1;
                Ok(self.push(Node::Num(v)))
            }
            Tok::Sym('(') => {
                self.pos += 1;
                let e = self.nest(|p| p.expr())?;
                self.expect(')', "to close the `(`")?;
                Ok(e)
            }
            Tok::Ident(name) => {
                self.pos += 1;
                let var = match name.as_str() {
                    "x" => Some(Node::Var(0)),
                    "y" => Some(Node::Var(1)),
                    "z" => Some(Node::Var(2)),
                    "pi" => Some(Node::Num(std::f64::consts::PI)),
                    _ => None,
                };
                if let Some(v) = var {
                    return Ok(self.push(v));
                }
                let func = match name.as_str() {
                    "sqrt" => Some(Ok(Func::Sqrt)),
                    "abs" => Some(Ok(Func::Abs)),
                    "sin" => Some(Ok(Func::Sin)),
                    "cos" => Some(Ok(Func::Cos)),
                    "exp" => Some(Ok(Func::Exp)),
                    "min" => Some(Err(BinOp::Min)),
                    "max" => Some(Err(BinOp::Max)),
                    _ => None,
                };
                let Some(func) = func else {
                    return if *self.peek() == Tok::Sym('(') {
                        err(
                            col,
                            format!("unknown function `{name}` (the functions are {FUNCTIONS})"),
                        )
                    } else {
                        err(
                            col,
                            format!("unknown variable `{name}` (the variables are x, y, z; pi is a constant)"),
                        )
                    };
                };
                self.expect('(', &format!("after the function `{name}`"))?;
                let a = self.nest(|p| p.expr())?;
                let node = match func {
                    Ok(f) => Node::Call(f, a),
                    Err(op) => {
                        self.expect(',', &format!("and a second argument: `{name}` takes two"))?;
                        let b = self.nest(|p| p.expr())?;
                        Node::Bin(op, a, b)
                    }
                };
                self.expect(')', &format!("to close the call of `{name}`"))?;
                Ok(self.push(node))
            }
            other => err(
                col,
                format!("expected a number, a variable, a function or `(`, found {other}"),
            ),
        }
    }
}

/// The value of a subtree without variables, for exponents (evaluated in f64 like the tape).
fn const_value(nodes: &[Node], i: u32) -> Option<f64> {
    // Post-order: evaluate the prefix of the arena up to `i` once, without recursion.
    let mut vals: Vec<Option<f64>> = Vec::with_capacity(i as usize + 1);
    for n in &nodes[..=i as usize] {
        let get = |j: &u32| vals[*j as usize];
        let v = match n {
            Node::Num(v) => Some(*v),
            Node::Var(_) => None,
            Node::Neg(a) => get(a).map(|a| -a),
            Node::Bin(op, a, b) => match (get(a), get(b)) {
                (Some(a), Some(b)) => Some(super::tape::apply_bin(*op, a, b)),
                _ => None,
            },
            Node::Pow(a, k) => get(a).map(|a| super::num::Num::powi(a, *k)),
            Node::Call(f, a) => get(a).map(|a| super::tape::apply_func(*f, a)),
        };
        vals.push(v);
    }
    vals[i as usize]
}

/// Parses a formula in `x`, `y`, `z`.
pub fn parse(src: &str) -> Result<Ast, FormulaError> {
    let toks = lex(src)?;
    let mut p = Parser {
        toks,
        pos: 0,
        nodes: Vec::new(),
        depth: 0,
    };
    if *p.peek() == Tok::End {
        return err(1, "the formula is empty");
    }
    let root = p.expr()?;
    if *p.peek() != Tok::End {
        let hint = match p.peek() {
            Tok::Ident(_) | Tok::Num(_) | Tok::Sym('(') => {
                " (write multiplication explicitly, as in `2*x`)"
            }
            _ => "",
        };
        return err(
            p.col(),
            format!(
                "expected an operator or the end of the formula, found {}{hint}",
                p.peek()
            ),
        );
    }
    Ok(Ast {
        nodes: p.nodes,
        root,
    })
}

/// The formula with each variable `v` replaced by `(v*k)`: `f(kx, ky, kz)`, whose zero set is the
/// surface scaled by `1/k`. A formula that does not lex is returned unchanged (validation reports it).
pub fn substitute_scaled(src: &str, k: f64) -> String {
    let Ok(toks) = lex(src) else {
        return src.to_string();
    };
    let mut is_var = vec![false; src.chars().count()];
    for (t, col) in &toks {
        if matches!(t, Tok::Ident(n) if n == "x" || n == "y" || n == "z") {
            is_var[col - 1] = true;
        }
    }
    let mut out = String::new();
    for (i, c) in src.chars().enumerate() {
        if is_var[i] {
            out.push_str(&format!("({c}*{k:e})"));
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(src: &str) -> FormulaError {
        parse(src).unwrap_err()
    }

    #[test]
    fn precedence_and_associativity() {
        let ast = parse("1 - 2 - 3").unwrap();
        // (1 - 2) - 3: the root's left child is itself a subtraction.
        let Node::Bin(BinOp::Sub, l, _) = ast.nodes[ast.root as usize] else {
            panic!("{ast:?}")
        };
        assert!(matches!(ast.nodes[l as usize], Node::Bin(BinOp::Sub, _, _)));
        // -x^2 is -(x^2).
        let ast = parse("-x^2").unwrap();
        assert!(matches!(ast.nodes[ast.root as usize], Node::Neg(_)));
    }

    #[test]
    fn exponents_must_be_integer_constants() {
        assert!(parse("x^-2").is_ok());
        assert!(parse("x^(1+1)").is_ok());
        assert!(parse("x^2^2").is_ok());
        let er = e("x^1.5");
        assert_eq!(er.column, 3);
        assert!(er.message.contains("integer"), "{er}");
        assert!(e("x^y").message.contains("integer"));
    }

    #[test]
    fn errors_name_the_column_and_what_was_expected() {
        let er = e("x + tan(y)");
        assert_eq!(er.column, 5);
        assert!(er.message.contains("unknown function `tan`"), "{er}");
        let er = e("x*w + 1");
        assert_eq!(er.column, 3);
        assert!(er.message.contains("unknown variable `w`"), "{er}");
        let er = e("(x + 1");
        assert_eq!(er.column, 7);
        assert!(er.message.contains("expected `)`"), "{er}");
        let er = e("2x");
        assert_eq!(er.column, 2);
        assert!(er.message.contains("multiplication"), "{er}");
        let er = e("min(x)");
        assert!(er.message.contains("two"), "{er}");
        assert_eq!(e("x # 2").column, 3);
        assert_eq!(e("").column, 1);
        assert_eq!(e("x +").column, 4);
    }

    #[test]
    fn scaling_substitutes_variables_only() {
        let f = substitute_scaled("x^2 + exp(y) - 2e3*z", 0.5);
        assert_eq!(f, "(x*5e-1)^2 + exp((y*5e-1)) - 2e3*(z*5e-1)");
        assert!(parse(&f).is_ok());
    }

    #[test]
    fn numbers_with_exponents() {
        let ast = parse("1e-3").unwrap();
        assert_eq!(ast.nodes[ast.root as usize], Node::Num(1e-3));
        let ast = parse(".5E+2").unwrap();
        assert_eq!(ast.nodes[ast.root as usize], Node::Num(50.0));
        assert!(e("1e999").message.contains("too large"));
        assert!(e("1.2.3").message.contains("malformed"));
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let deep = "(".repeat(100_000) + "x" + &")".repeat(100_000);
        assert!(e(&deep).message.contains("nests"));
        let minus = "-".repeat(100_000) + "x";
        assert!(e(&minus).message.contains("nests"));
        let long_chain = vec!["x"; 100_000].join("+");
        assert!(parse(&long_chain).is_ok());
    }

    proptest::proptest! {
        #[test]
        fn no_input_panics(s in "\\PC{0,40}") {
            let _ = parse(&s);
        }

        #[test]
        fn no_formula_like_input_panics(s in "[xyz0-9.e+*/^()sqrtabinco,mxp -]{0,60}") {
            if let Ok(ast) = parse(&s) {
                let tape = super::super::tape::Tape::compile(&ast);
                let _ = tape.eval_f64([0.5, -0.25, 2.0]);
            }
        }
    }
}
