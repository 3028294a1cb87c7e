//! Expressions as a session writes them: numbers, names, `+ - * / ^`, calls, comparisons and
//! `&&`/`||` inside `if`, read into a syntax tree that keeps each name's place in the text.

/// A place in an expression's text: byte offsets `start..end`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// A comparison, true where `left op right`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmpOp {
    Lt,
    Le,
    Gt,
    Ge,
}

/// An expression as written.
#[derive(Debug, Clone, PartialEq)]
pub enum Ast {
    Num(f64),
    Name(String, Span),
    Neg(Box<Ast>),
    Bin(BinOp, Box<Ast>, Box<Ast>),
    Call(String, Span, Vec<Ast>),
    Cmp(CmpOp, Box<Ast>, Box<Ast>),
    And(Box<Ast>, Box<Ast>),
    Or(Box<Ast>, Box<Ast>),
}

/// Why an expression could not be read: the offending token and its place.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntaxError {
    pub span: Span,
    /// The token as written (empty at the end of the text).
    pub token: String,
    pub message: String,
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(&'static str),
    End,
}

/// Splits `text` into tokens with their places.
fn tokens(text: &str) -> Result<Vec<(Tok, Span)>, SyntaxError> {
    const OPS: [&str; 15] = [
        "<=", ">=", "&&", "||", "**", "+", "-", "*", "/", "^", "(", ")", ",", "<", ">",
    ];
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        if c.is_ascii_digit() || (c == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
                let mut j = i + 1;
                if j < bytes.len() && (bytes[j] == b'+' || bytes[j] == b'-') {
                    j += 1;
                }
                if j < bytes.len() && bytes[j].is_ascii_digit() {
                    i = j;
                    while i < bytes.len() && bytes[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let span = Span { start, end: i };
            let lit = &text[start..i];
            let value: f64 = lit.parse().map_err(|_| SyntaxError {
                span,
                token: lit.to_string(),
                message: "not a number".into(),
            })?;
            if value.is_infinite() {
                return Err(SyntaxError {
                    span,
                    token: lit.to_string(),
                    message: "a number beyond the largest a double holds (1.8e308)".into(),
                });
            }
            out.push((Tok::Num(value), span));
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' || c >= 0x80 {
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' || bytes[i] >= 0x80)
            {
                i += 1;
            }
            let span = Span { start, end: i };
            out.push((Tok::Name(text[start..i].to_string()), span));
            continue;
        }
        let op = OPS.iter().find(|op| text[i..].starts_with(**op));
        match op {
            Some(op) => {
                i += op.len();
                let op = if *op == "**" { "^" } else { op };
                out.push((Tok::Op(op), Span { start, end: i }));
            }
            None => {
                let ch = text[i..].chars().next().unwrap_or('?');
                return Err(SyntaxError {
                    span: Span {
                        start,
                        end: i + ch.len_utf8(),
                    },
                    token: ch.to_string(),
                    message: "unexpected character".into(),
                });
            }
        }
    }
    let end = Span {
        start: text.len(),
        end: text.len(),
    };
    out.push((Tok::End, end));
    Ok(out)
}

/// Reads one expression.
pub fn parse(text: &str) -> Result<Ast, SyntaxError> {
    let toks = tokens(text)?;
    let mut p = Parser { text, toks, at: 0 };
    let ast = p.expr(0)?;
    match p.peek() {
        Tok::End => Ok(ast),
        _ => Err(p.error("expected an operator or the end of the expression")),
    }
}

struct Parser<'a> {
    text: &'a str,
    toks: Vec<(Tok, Span)>,
    at: usize,
}

/// Binding powers (left, right) of the infix operators, lowest first; `^` is
/// right-associative and binds tighter than a unary minus on its left (`-x^2` is −(x²)).
fn infix(op: &str) -> Option<(u8, u8)> {
    Some(match op {
        "||" => (1, 2),
        "&&" => (3, 4),
        "<" | "<=" | ">" | ">=" => (5, 6),
        "+" | "-" => (7, 8),
        "*" | "/" => (9, 10),
        "^" => (14, 13),
        _ => return None,
    })
}

/// Binding power of a unary minus: below `^`, above `*`.
const UNARY: u8 = 11;

impl Parser<'_> {
    fn peek(&self) -> &Tok {
        &self.toks[self.at].0
    }

    fn span(&self) -> Span {
        self.toks[self.at].1
    }

    fn error(&self, message: &str) -> SyntaxError {
        let span = self.span();
        SyntaxError {
            span,
            token: self.text[span.start..span.end].to_string(),
            message: message.to_string(),
        }
    }

    fn bump(&mut self) -> (Tok, Span) {
        let t = self.toks[self.at].clone();
        if self.at + 1 < self.toks.len() {
            self.at += 1;
        }
        t
    }

    fn expect(&mut self, op: &'static str, message: &str) -> Result<(), SyntaxError> {
        if *self.peek() == Tok::Op(op) {
            self.bump();
            Ok(())
        } else {
            Err(self.error(message))
        }
    }

    fn expr(&mut self, min_bp: u8) -> Result<Ast, SyntaxError> {
        let mut left = self.prefix()?;
        while let Tok::Op(op) = self.peek() {
            let op = *op;
            let Some((lbp, rbp)) = infix(op) else { break };
            if lbp < min_bp {
                break;
            }
            self.bump();
            let right = self.expr(rbp)?;
            let (l, r) = (Box::new(left), Box::new(right));
            left = match op {
                "+" => Ast::Bin(BinOp::Add, l, r),
                "-" => Ast::Bin(BinOp::Sub, l, r),
                "*" => Ast::Bin(BinOp::Mul, l, r),
                "/" => Ast::Bin(BinOp::Div, l, r),
                "^" => Ast::Bin(BinOp::Pow, l, r),
                "<" => Ast::Cmp(CmpOp::Lt, l, r),
                "<=" => Ast::Cmp(CmpOp::Le, l, r),
                ">" => Ast::Cmp(CmpOp::Gt, l, r),
                ">=" => Ast::Cmp(CmpOp::Ge, l, r),
                "&&" => Ast::And(l, r),
                _ => Ast::Or(l, r),
            };
        }
        Ok(left)
    }

    fn prefix(&mut self) -> Result<Ast, SyntaxError> {
        let (tok, span) = self.bump();
        match tok {
            Tok::Num(v) => Ok(Ast::Num(v)),
            Tok::Op("-") => Ok(Ast::Neg(Box::new(self.expr(UNARY)?))),
            Tok::Op("+") => self.expr(UNARY),
            Tok::Op("(") => {
                let inner = self.expr(0)?;
                self.expect(")", "expected `)`")?;
                Ok(inner)
            }
            Tok::Name(name) => {
                if *self.peek() != Tok::Op("(") {
                    return Ok(Ast::Name(name, span));
                }
                self.bump();
                let mut args = Vec::new();
                if *self.peek() == Tok::Op(")") {
                    self.bump();
                } else {
                    loop {
                        args.push(self.expr(0)?);
                        if *self.peek() == Tok::Op(",") {
                            self.bump();
                            continue;
                        }
                        self.expect(")", "expected `,` or `)` in the arguments")?;
                        break;
                    }
                }
                Ok(Ast::Call(name, span, args))
            }
            Tok::End => {
                self.at = self.toks.len() - 1;
                Err(self.error("the expression ends where a value was expected"))
            }
            Tok::Op(_) => {
                self.at -= 1;
                let e = self.error("expected a number, a name or `(`");
                self.at += 1;
                Err(e)
            }
        }
    }
}
