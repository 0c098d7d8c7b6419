//! PySPH's `.npz` output (what PySPH writes without h5py): a NumPy zip archive (entries stored
//! or deflated) with `version.npy` (2) and `particles.npy`, a 0-d object array holding one
//! pickled Python dictionary:
//!
//! ```text
//! { "<array>": { "properties": {...}, "constants": {...},
//!                "arrays": { "<property>": numpy.ndarray, ... }, ... }, ... }
//! ```
//!
//! The pickle is run by a small stack machine for the opcodes Python's pickle protocols 2 to
//! 5 use for dictionaries, lists, tuples, strings, numbers and NumPy arrays; it builds no
//! Python object, it records each call (`numpy._core.multiarray._reconstruct`,
//! `numpy.dtype`) with its arguments and state, from which the arrays are decoded: dtype
//! string (`f8`, `i4`, `u4`, …) and byte order, shape and raw bytes. Any other opcode or
//! layout is an error naming the file and the byte offset.

use crate::error::{IoError, Location};
use crate::pysph::{ParticleArray, PropertyValues};
use std::io::Read;

/// Reads every particle array of the `.npz` in `bytes`.
pub(crate) fn read(bytes: &[u8], name: &str) -> Result<Vec<ParticleArray>, IoError> {
    let bad = |what: String| IoError::parse(name, Location::File, what);
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| bad(format!("not a readable .npz (zip) archive: {e}")))?;
    let mut entry = |entry: &str| -> Result<Vec<u8>, IoError> {
        let mut file = zip.by_name(entry).map_err(|e| {
            bad(format!(
                "no {entry} in the archive, so not PySPH output (version 2): {e}"
            ))
        })?;
        let mut out = Vec::new();
        file.read_to_end(&mut out)
            .map_err(|e| bad(format!("cannot inflate {entry}: {e}")))?;
        Ok(out)
    };
    let version = entry("version.npy")?;
    let particles = entry("particles.npy")?;
    let (descr, body) = npy_header(&version).map_err(|e| bad(format!("version.npy: {e}")))?;
    let v = match (descr, body.len()) {
        ("<i8", 8) => i64::from_le_bytes(body[..8].try_into().unwrap_or([0; 8])),
        ("<i4", 4) => i64::from(i32::from_le_bytes(body[..4].try_into().unwrap_or([0; 4]))),
        _ => -1,
    };
    if v != 2 {
        return Err(bad(format!(
            "PySPH output version {v} (descr {descr}): only version 2, what PySPH 1.0 writes, \
             is read"
        )));
    }
    let (descr, body) = npy_header(&particles).map_err(|e| bad(format!("particles.npy: {e}")))?;
    if descr != "|O" {
        return Err(bad(format!(
            "particles.npy holds {descr}, not the pickled dictionary PySPH writes"
        )));
    }
    let header = particles.len() - body.len();
    let mut machine = Machine::default();
    let root = machine
        .run(body)
        .map_err(|(at, what)| bad(format!("particles.npy byte {}: {what}", header + at)))?;
    let root = machine.unwrap_array(root);
    let arrays = machine
        .dict(root)
        .ok_or_else(|| bad("particles.npy: not a dictionary of particle arrays".to_owned()))?;
    let mut out = Vec::with_capacity(arrays.len());
    for (key, info) in arrays {
        let array = machine
            .string(key)
            .ok_or_else(|| bad("particles.npy: a particle array name that is not text".into()))?;
        let fail = |what: String| bad(format!("particle array {array:?}: {what}"));
        let info = machine
            .dict(info)
            .ok_or_else(|| fail("not a dictionary".into()))?;
        let props = info
            .iter()
            .find(|(k, _)| machine.string(*k).as_deref() == Some("arrays"))
            .and_then(|(_, v)| machine.dict(*v))
            .ok_or_else(|| fail("no dictionary \"arrays\" of property values".into()))?;
        let mut properties = Vec::with_capacity(props.len());
        for (k, v) in props {
            let prop = machine
                .string(k)
                .ok_or_else(|| fail("a property name that is not text".into()))?;
            let values = machine
                .ndarray(v)
                .map_err(|e| fail(format!("property {prop:?}: {e}")))?;
            properties.push((prop, values));
        }
        out.push(ParticleArray {
            name: array,
            properties,
        });
    }
    Ok(out)
}

/// The `descr` of a `.npy` header and the bytes after the header.
fn npy_header(bytes: &[u8]) -> Result<(&str, &[u8]), String> {
    if !bytes.starts_with(b"\x93NUMPY") || bytes.len() < 10 {
        return Err("not a .npy array (no \\x93NUMPY magic)".into());
    }
    let (len, start): (usize, usize) = match bytes[6] {
        1 => (usize::from(u16::from_le_bytes([bytes[8], bytes[9]])), 10),
        2 | 3 if bytes.len() >= 12 => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
        v => return Err(format!(".npy format version {v} is not known")),
    };
    let end = start
        .checked_add(len)
        .filter(|&e| e <= bytes.len())
        .ok_or("the .npy header runs past the end")?;
    let header = std::str::from_utf8(&bytes[start..end]).map_err(|_| "a .npy header not text")?;
    let descr = header
        .split_once("'descr':")
        .and_then(|(_, rest)| rest.trim_start().strip_prefix('\''))
        .and_then(|rest| rest.split_once('\''))
        .map(|(d, _)| d)
        .ok_or("the .npy header names no descr")?;
    Ok((descr, &bytes[end..]))
}

/// A value the pickle built, by its index in the machine's arena.
#[derive(Debug, Clone)]
enum Obj {
    None,
    /// A value the arrays do not need (booleans, reals).
    Other,
    Int(i64),
    Str(String),
    Bytes(Vec<u8>),
    Tuple(Vec<usize>),
    List(Vec<usize>),
    Dict(Vec<(usize, usize)>),
    /// `module.name`.
    Global(String, String),
    /// A call `callable(*args)`, then its state (BUILD).
    Call {
        callable: usize,
        args: usize,
        state: Option<usize>,
    },
}

/// The pickle stack machine: values live in `arena`, the stack and the memo hold indices.
#[derive(Default)]
struct Machine {
    arena: Vec<Obj>,
}

type Step<T> = Result<T, (usize, String)>;

impl Machine {
    fn add(&mut self, o: Obj) -> usize {
        self.arena.push(o);
        self.arena.len() - 1
    }

    /// Runs the pickle in `data` and returns its result.
    fn run(&mut self, data: &[u8]) -> Step<usize> {
        let mut stack: Vec<usize> = Vec::new();
        let mut marks: Vec<usize> = Vec::new();
        let mut memo: Vec<Option<usize>> = Vec::new();
        let mut pos = 0usize;
        let take = |pos: &mut usize, n: usize| -> Step<&[u8]> {
            let end = pos
                .checked_add(n)
                .filter(|&e| e <= data.len())
                .ok_or((*pos, "the pickle ends early".to_owned()))?;
            let out = &data[*pos..end];
            *pos = end;
            Ok(out)
        };
        let uint = |b: &[u8]| b.iter().rev().fold(0u64, |a, &x| (a << 8) | u64::from(x));
        loop {
            let at = pos;
            let op = take(&mut pos, 1)?[0];
            let err = |what: &str| (at, what.to_owned());
            let pop = |stack: &mut Vec<usize>| stack.pop().ok_or(err("stack underflow"));
            let pop_mark = |stack: &mut Vec<usize>, marks: &mut Vec<usize>| {
                let m = marks.pop().ok_or(err("no MARK"))?;
                if m > stack.len() {
                    return Err(err("MARK past the stack"));
                }
                Ok(stack.split_off(m))
            };
            match op {
                0x80 => {
                    take(&mut pos, 1)?;
                } // PROTO
                0x95 => {
                    take(&mut pos, 8)?;
                } // FRAME
                b'.' => return pop(&mut stack), // STOP
                b'(' => marks.push(stack.len()),
                b'N' => stack.push(self.add(Obj::None)),
                0x88 | 0x89 => stack.push(self.add(Obj::Other)),
                b'K' | b'M' | b'J' => {
                    let n = match op {
                        b'K' => 1,
                        b'M' => 2,
                        _ => 4,
                    };
                    let b = take(&mut pos, n)?;
                    let v = if op == b'J' {
                        i64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    } else {
                        uint(b) as i64
                    };
                    stack.push(self.add(Obj::Int(v)));
                }
                0x8a => {
                    // LONG1: little-endian two's complement of n bytes.
                    let n = usize::from(take(&mut pos, 1)?[0]);
                    let b = take(&mut pos, n)?;
                    if n > 8 {
                        return Err(err("an integer wider than 64 bits"));
                    }
                    let mut v = uint(b) as i64;
                    if n > 0 && n < 8 && b[n - 1] & 0x80 != 0 {
                        v -= 1i64 << (8 * n);
                    }
                    stack.push(self.add(Obj::Int(v)));
                }
                b'G' => {
                    take(&mut pos, 8)?;
                    stack.push(self.add(Obj::Other));
                }
                0x8c | b'X' | 0x8d => {
                    let n = match op {
                        0x8c => 1,
                        b'X' => 4,
                        _ => 8,
                    };
                    let len = uint(take(&mut pos, n)?) as usize;
                    let b = take(&mut pos, len)?;
                    let s = std::str::from_utf8(b).map_err(|_| err("text not UTF-8"))?;
                    stack.push(self.add(Obj::Str(s.to_owned())));
                }
                b'C' | b'B' | 0x8e | b'U' | b'T' => {
                    // SHORT_BINBYTES, BINBYTES, BINBYTES8, SHORT_BINSTRING, BINSTRING
                    let n = match op {
                        b'C' | b'U' => 1,
                        b'B' | b'T' => 4,
                        _ => 8,
                    };
                    let len = uint(take(&mut pos, n)?) as usize;
                    let b = take(&mut pos, len)?.to_vec();
                    stack.push(self.add(Obj::Bytes(b)));
                }
                b')' => stack.push(self.add(Obj::Tuple(Vec::new()))),
                0x85..=0x87 => {
                    let n = usize::from(op - 0x84);
                    if stack.len() < n {
                        return Err(err("stack underflow"));
                    }
                    let items = stack.split_off(stack.len() - n);
                    stack.push(self.add(Obj::Tuple(items)));
                }
                b't' => {
                    let items = pop_mark(&mut stack, &mut marks)?;
                    stack.push(self.add(Obj::Tuple(items)));
                }
                b']' => stack.push(self.add(Obj::List(Vec::new()))),
                b'l' => {
                    let items = pop_mark(&mut stack, &mut marks)?;
                    stack.push(self.add(Obj::List(items)));
                }
                b'}' => stack.push(self.add(Obj::Dict(Vec::new()))),
                b'd' => {
                    let items = pop_mark(&mut stack, &mut marks)?;
                    let pairs = items.chunks_exact(2).map(|p| (p[0], p[1])).collect();
                    stack.push(self.add(Obj::Dict(pairs)));
                }
                b'a' | b'e' => {
                    let items = if op == b'a' {
                        vec![pop(&mut stack)?]
                    } else {
                        pop_mark(&mut stack, &mut marks)?
                    };
                    let list = *stack.last().ok_or(err("stack underflow"))?;
                    match &mut self.arena[list] {
                        Obj::List(v) => v.extend(items),
                        _ => return Err(err("APPEND to a non-list")),
                    }
                }
                b's' | b'u' => {
                    let items = if op == b's' {
                        let v = pop(&mut stack)?;
                        let k = pop(&mut stack)?;
                        vec![k, v]
                    } else {
                        pop_mark(&mut stack, &mut marks)?
                    };
                    let dict = *stack.last().ok_or(err("stack underflow"))?;
                    match &mut self.arena[dict] {
                        Obj::Dict(d) => d.extend(items.chunks_exact(2).map(|p| (p[0], p[1]))),
                        _ => return Err(err("SETITEM on a non-dictionary")),
                    }
                }
                0x94 => {
                    let top = *stack.last().ok_or(err("stack underflow"))?;
                    memo.push(Some(top));
                }
                b'q' | b'r' => {
                    let n = if op == b'q' { 1 } else { 4 };
                    let i = uint(take(&mut pos, n)?) as usize;
                    let top = *stack.last().ok_or(err("stack underflow"))?;
                    if i >= memo.len() {
                        if i > data.len() {
                            return Err(err("memo index past the pickle"));
                        }
                        memo.resize(i + 1, None);
                    }
                    memo[i] = Some(top);
                }
                b'h' | b'j' => {
                    let n = if op == b'h' { 1 } else { 4 };
                    let i = uint(take(&mut pos, n)?) as usize;
                    let v = memo
                        .get(i)
                        .copied()
                        .flatten()
                        .ok_or(err("memo entry not set"))?;
                    stack.push(v);
                }
                0x93 => {
                    let name = pop(&mut stack)?;
                    let module = pop(&mut stack)?;
                    let (Some(m), Some(n)) = (self.string(module), self.string(name)) else {
                        return Err(err("STACK_GLOBAL of non-text names"));
                    };
                    stack.push(self.add(Obj::Global(m, n)));
                }
                b'c' => {
                    let mut line = || -> Step<String> {
                        let rest = &data[pos..];
                        let n = rest
                            .iter()
                            .position(|&b| b == b'\n')
                            .ok_or(err("GLOBAL without a newline"))?;
                        let s = String::from_utf8_lossy(&rest[..n]).into_owned();
                        pos += n + 1;
                        Ok(s)
                    };
                    let (m, n) = (line()?, line()?);
                    stack.push(self.add(Obj::Global(m, n)));
                }
                b'R' => {
                    let args = pop(&mut stack)?;
                    let callable = pop(&mut stack)?;
                    stack.push(self.add(Obj::Call {
                        callable,
                        args,
                        state: None,
                    }));
                }
                b'b' => {
                    let state = pop(&mut stack)?;
                    let object = *stack.last().ok_or(err("stack underflow"))?;
                    match &mut self.arena[object] {
                        Obj::Call { state: s, .. } => *s = Some(state),
                        _ => return Err(err("BUILD of an object not made by a call")),
                    }
                }
                other => return Err(err(&format!("pickle opcode 0x{other:02x} is not read"))),
            }
        }
    }

    fn string(&self, i: usize) -> Option<String> {
        match &self.arena[i] {
            Obj::Str(s) => Some(s.clone()),
            Obj::Bytes(b) => String::from_utf8(b.clone()).ok(),
            _ => None,
        }
    }

    fn dict(&self, i: usize) -> Option<Vec<(usize, usize)>> {
        match &self.arena[i] {
            Obj::Dict(d) => Some(d.clone()),
            _ => None,
        }
    }

    /// A 0-d object array's one element (what `numpy.save` pickles for a dictionary is the
    /// dictionary itself; an array around it is unwrapped).
    fn unwrap_array(&self, i: usize) -> usize {
        if let Some((_, _, _, Some(items))) = self.array_parts(i) {
            if let [one] = items[..] {
                return one;
            }
        }
        i
    }

    /// The dtype string, byte order, shape and raw bytes (or object items) of an ndarray
    /// call.
    #[allow(clippy::type_complexity)]
    fn array_parts(&self, i: usize) -> Option<(String, char, Vec<usize>, Option<Vec<usize>>)> {
        let Obj::Call {
            callable,
            state: Some(state),
            ..
        } = &self.arena[i]
        else {
            return None;
        };
        match &self.arena[*callable] {
            Obj::Global(m, n) if m.starts_with("numpy") && n == "_reconstruct" => {}
            _ => return None,
        }
        let Obj::Tuple(st) = &self.arena[*state] else {
            return None;
        };
        let [_, shape, dtype, _, data] = st[..] else {
            return None;
        };
        let Obj::Tuple(shape) = &self.arena[shape] else {
            return None;
        };
        let shape: Vec<usize> = shape
            .iter()
            .map(|&d| match self.arena[d] {
                Obj::Int(n) => usize::try_from(n).ok(),
                _ => None,
            })
            .collect::<Option<_>>()?;
        let Obj::Call {
            args,
            state: dstate,
            ..
        } = &self.arena[dtype]
        else {
            return None;
        };
        let Obj::Tuple(a) = &self.arena[*args] else {
            return None;
        };
        let descr = self.string(*a.first()?)?;
        let order = dstate
            .and_then(|s| match &self.arena[s] {
                Obj::Tuple(t) => t.get(1).and_then(|&o| self.string(o)),
                _ => None,
            })
            .and_then(|o| o.chars().next())
            .unwrap_or('|');
        let items = match &self.arena[data] {
            Obj::List(items) => Some(items.clone()),
            _ => None,
        };
        Some((descr, order, shape, items))
    }

    /// The values of a numeric ndarray (flattened, C order).
    fn ndarray(&self, i: usize) -> Result<PropertyValues, String> {
        let (descr, order, shape, items) = self
            .array_parts(i)
            .ok_or("not a NumPy array as numpy pickles one")?;
        if items.is_some() {
            return Ok(PropertyValues::Other(format!("objects ({descr})")));
        }
        let Obj::Call {
            state: Some(state), ..
        } = &self.arena[i]
        else {
            return Err("no array state".into());
        };
        let Obj::Tuple(st) = &self.arena[*state] else {
            return Err("no array state".into());
        };
        let Some(Obj::Bytes(raw)) = st.get(4).map(|&d| &self.arena[d]) else {
            return Err("the array's data is not raw bytes".into());
        };
        let n = shape
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .ok_or("a shape too large")?;
        let kind = descr.chars().next().unwrap_or('?');
        let size: usize = descr
            .get(1..)
            .and_then(|s| s.parse().ok())
            .filter(|&s| (1..=8).contains(&s))
            .ok_or_else(|| format!("dtype {descr} is not a number type"))?;
        if n.checked_mul(size) != Some(raw.len()) {
            return Err(format!(
                "{} bytes of data for {n} values of {descr}",
                raw.len()
            ));
        }
        let big = order == '>';
        let word = |c: &[u8]| -> u64 {
            let it = c.iter().enumerate();
            if big {
                it.fold(0u64, |a, (_, &b)| (a << 8) | u64::from(b))
            } else {
                it.rev().fold(0u64, |a, (_, &b)| (a << 8) | u64::from(b))
            }
        };
        let words = raw.chunks_exact(size).map(word);
        Ok(match (kind, size) {
            ('f', 8) => PropertyValues::Float(words.map(f64::from_bits).collect()),
            ('f', 4) => {
                PropertyValues::Float(words.map(|w| f64::from(f32::from_bits(w as u32))).collect())
            }
            ('u' | 'b', 1 | 2 | 4) => PropertyValues::Int(words.map(|w| w as i64).collect()),
            ('u', 8) => {
                let v: Vec<u64> = words.collect();
                if v.iter().all(|&x| i64::try_from(x).is_ok()) {
                    PropertyValues::Int(v.into_iter().map(|x| x as i64).collect())
                } else {
                    PropertyValues::Float(v.into_iter().map(|x| x as f64).collect())
                }
            }
            ('i', 1 | 2 | 4 | 8) => {
                let shift = 64 - 8 * size as u32;
                PropertyValues::Int(words.map(|w| ((w << shift) as i64) >> shift).collect())
            }
            _ => PropertyValues::Other(format!("dtype {descr}")),
        })
    }
}
