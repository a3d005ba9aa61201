//! A `.brdf` file's shader wrapped for vk-render's shaders: `shaders/brdf/analytic.glsl` of one model.
//!
//! GLSL has one namespace, and the files and vk-render's shaders use the same words (`PI`, `sqr`, `G`,
//! `Fresnel`, `GGX`, ...). So every identifier of the file's own (its functions, constants, structs, locals and
//! its parameters) is given the prefix [`PREFIX`], which no name of vk-render's shaders has; GLSL's own words,
//! swizzles and struct members are left as they are. A file that defines a built-in function again with
//! another meaning (BRDF Explorer's `reflect(L, N)` and `smoothstep`), which glslang's Vulkan target refuses,
//! gets that name prefixed too, calls and definition alike. Each line keeps its line in the file (`#line`),
//! and the compiler's messages are mapped back to the file's own names and lines.
//!
//! The parameters are globals of the file's names, set from the material's values in the parameter buffer
//! before each call, so that they stay visible in every function of the file (and a function argument of the
//! same name shadows them, as in BRDF Explorer).

use std::collections::HashSet;

use crate::names::{is_builtin, is_builtin_function};
use crate::parse::ParseError;
use crate::{Parameter, ParameterKind};

/// What every name of the file's own is prefixed with.
pub const PREFIX: &str = "usr_";

/// The file name the `#line` directives give, replaced by the file's path in messages (a path may hold
/// characters a directive's string cannot).
const LINE_FILE: &str = "BRDF_FILE";

/// The source-string numbers of GLSL ES's `#line` (it takes no names): the template the file is put into
/// (vk-render's translated shader), the file's own lines, and the wrapper's functions after them.
const ES_TEMPLATE: u32 = 0;
const ES_FILE: u32 = 1;
const ES_WRAPPER: u32 = 2;

/// Which compiler the wrapped GLSL goes to: how its `#line` directives name the file's lines, and how the
/// compiler's messages are read back ([`file_error`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The renderer's: shaderc (glslang) compiling GLSL 4.60 for Vulkan, whose `#line` takes a file name
    /// (`GL_GOOGLE_cpp_style_line_directive`).
    Vulkan,
    /// The browser's: WebGL2 compiling GLSL ES 3.00, whose `#line` takes a source-string number, and whose
    /// messages read `ERROR: SOURCE:LINE: ...`. The text goes in place of the translated shaders' hook (the
    /// forward passes translated at build time with a stand-in model: build/webgl.rs).
    WebGl,
}

impl Target {
    /// The `#line` directive that numbers the next line `line` of the file's own text.
    fn file_line(self, line: usize) -> String {
        match self {
            Target::Vulkan => format!("#line {line} \"{LINE_FILE}\"\n"),
            Target::WebGl => format!("#line {line} {ES_FILE}\n"),
        }
    }

    /// The `#line` directive that begins the wrapper's own functions.
    fn wrapper_lines(self) -> String {
        match self {
            Target::Vulkan => "#line 1 \"brdf/analytic.glsl\"\n".to_string(),
            Target::WebGl => format!("#line 1 {ES_WRAPPER}\n"),
        }
    }
}

/// The text of one token of the shader: an identifier, or anything else (kept as written).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Token<'a> {
    Identifier(&'a str),
    Comment(&'a str),
    Space(&'a str),
    Other(&'a str),
}

impl<'a> Token<'a> {
    fn text(self) -> &'a str {
        match self {
            Token::Identifier(t) | Token::Comment(t) | Token::Space(t) | Token::Other(t) => t,
        }
    }

    fn is_significant(self) -> bool {
        !matches!(self, Token::Comment(_) | Token::Space(_))
    }
}

/// Splits GLSL text into tokens: identifiers, numbers (with their exponents and suffixes), comments, white
/// space, and single characters.
fn tokens(text: &str) -> Vec<Token<'_>> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let start = at;
        let c = bytes[at];
        let token = if c.is_ascii_alphabetic() || c == b'_' {
            while at < bytes.len() && (bytes[at].is_ascii_alphanumeric() || bytes[at] == b'_') {
                at += 1;
            }
            Token::Identifier(&text[start..at])
        } else if c.is_ascii_digit() || (c == b'.' && bytes.get(at + 1).is_some_and(u8::is_ascii_digit)) {
            while at < bytes.len() {
                let b = bytes[at];
                let exponent_sign = (b == b'+' || b == b'-') && matches!(bytes[at - 1], b'e' | b'E');
                if !(b.is_ascii_alphanumeric() || b == b'.' || b == b'_' || exponent_sign) {
                    break;
                }
                at += 1;
            }
            Token::Other(&text[start..at])
        } else if text[at..].starts_with("//") {
            at = text[at..].find('\n').map_or(bytes.len(), |end| at + end);
            Token::Comment(&text[start..at])
        } else if text[at..].starts_with("/*") {
            at = text[at + 2..].find("*/").map_or(bytes.len(), |end| at + 2 + end + 2);
            Token::Comment(&text[start..at])
        } else if c.is_ascii_whitespace() {
            while at < bytes.len() && bytes[at].is_ascii_whitespace() {
                at += 1;
            }
            Token::Space(&text[start..at])
        } else {
            // One character, however many bytes it takes.
            at += text[at..].chars().next().map_or(1, char::len_utf8);
            Token::Other(&text[start..at])
        };
        out.push(token);
    }
    out
}

/// What the file declares at global scope that decides how its names are rewritten.
#[derive(Default)]
struct Declarations<'a> {
    /// Built-in functions the file defines again.
    redefined: HashSet<&'a str>,
    /// The file's struct types.
    structs: HashSet<&'a str>,
}

/// The significant tokens with their index among all tokens and their line (0 for the first line).
fn significant<'a>(all: &[Token<'a>]) -> Vec<(usize, usize, Token<'a>)> {
    let mut line = 0;
    let mut out = Vec::new();
    for (index, token) in all.iter().enumerate() {
        if token.is_significant() {
            out.push((index, line, *token));
        }
        line += token.text().matches('\n').count();
    }
    out
}

/// A function vk-render calls in a file: its name, its return and argument types, and how messages quote it.
struct Signature {
    name: &'static str,
    returns: &'static str,
    arguments: [&'static str; 5],
    quoted: &'static str,
    /// The section that must define it.
    section: &'static str,
}

/// The model itself.
const BRDF: Signature = Signature {
    name: "BRDF",
    returns: "vec3",
    arguments: ["vec3"; 5],
    quoted: "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)",
    section: "shader",
};

/// The isFunc section's sampler: a direction towards the light drawn for the view V from the uniform u.
const SAMPLE: Signature = Signature {
    name: "sampleBRDF",
    returns: "vec3",
    arguments: ["vec3", "vec3", "vec3", "vec3", "vec2"],
    quoted: "vec3 sampleBRDF(vec3 V, vec3 N, vec3 X, vec3 Y, vec2 u)",
    section: "isFunc",
};

/// The isFunc section's density: the sampler's, per solid angle, of drawing L for the view V.
const PDF: Signature = Signature {
    name: "pdfBRDF",
    returns: "float",
    arguments: ["vec3"; 5],
    quoted: "float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)",
    section: "isFunc",
};

/// Finds the file's global declarations and checks that it defines each of `required` (and anything of
/// [`BRDF`], [`SAMPLE`] or [`PDF`]'s names with their types). `lines[k]` is the file's line number of the text's
/// line k.
fn declarations<'a>(
    significant: &[(usize, usize, Token<'a>)],
    lines: &[usize],
    required: &[&Signature],
) -> Result<Declarations<'a>, ParseError> {
    let file_line = |line: usize| lines.get(line).copied();
    let mut found = Declarations::default();
    let mut depth = 0usize;
    let mut defined: HashSet<&str> = HashSet::new();
    for (k, &(_, line, token)) in significant.iter().enumerate() {
        match token {
            Token::Other("{") => depth += 1,
            Token::Other("}") => depth = depth.saturating_sub(1),
            Token::Identifier("struct") if depth == 0 => {
                if let Some((_, _, Token::Identifier(name))) = significant.get(k + 1) {
                    found.structs.insert(name);
                }
            }
            Token::Identifier(name) if depth == 0 => {
                let opens_call = matches!(significant.get(k + 1), Some((_, _, Token::Other("("))));
                let after_type = k > 0 && matches!(significant[k - 1].2, Token::Identifier(_));
                if !(opens_call && after_type) {
                    continue;
                }
                if is_builtin_function(name) {
                    found.redefined.insert(name);
                }
                let Some(signature) = [&BRDF, &SAMPLE, &PDF].into_iter().find(|s| s.name == name) else { continue };
                let (arguments, end) = argument_types(significant, k + 1);
                let returns = significant[k - 1].2.text();
                if returns != signature.returns || arguments != signature.arguments {
                    return Err(ParseError {
                        line: file_line(line),
                        message: format!(
                            "the {} section defines `{returns} {name}({})`: vk-render calls `{}`",
                            signature.section,
                            arguments.join(", "),
                            signature.quoted
                        ),
                    });
                }
                if matches!(significant.get(end + 1), Some((_, _, Token::Other("{")))) {
                    defined.insert(signature.name);
                }
            }
            _ => {}
        }
    }
    if let Some(missing) = required.iter().find(|s| !defined.contains(s.name)) {
        return Err(ParseError {
            line: None,
            message: format!("the {} section defines no function `{}`", missing.section, missing.quoted),
        });
    }
    Ok(found)
}

/// The type of each argument of the function whose `(` is significant token `open`, and the index of its
/// `)`: each argument's last identifier but its name, qualifiers (`in`, `const`, precision) left out.
fn argument_types(significant: &[(usize, usize, Token<'_>)], open: usize) -> (Vec<String>, usize) {
    let mut arguments = Vec::new();
    let mut current: Vec<&str> = Vec::new();
    let mut depth = 0;
    for (k, &(_, _, token)) in significant.iter().enumerate().skip(open) {
        match token {
            Token::Other("(") => depth += 1,
            Token::Other(")") if depth == 1 => {
                if !current.is_empty() {
                    arguments.push(argument_type(&current));
                }
                return (arguments, k);
            }
            Token::Other(")") => depth -= 1,
            Token::Other(",") if depth == 1 => arguments.push(argument_type(&std::mem::take(&mut current))),
            Token::Identifier(word) if depth == 1 => current.push(word),
            _ => {}
        }
    }
    (arguments, significant.len())
}

fn argument_type(words: &[&str]) -> String {
    const QUALIFIERS: [&str; 8] = ["in", "out", "inout", "const", "highp", "mediump", "lowp", "precise"];
    let types: Vec<&str> = words.iter().copied().filter(|w| !QUALIFIERS.contains(w)).collect();
    match types.as_slice() {
        [] => String::new(),
        [only] => (*only).to_string(),
        [.., kind, _name] => (*kind).to_string(),
    }
}

/// The file's shader with every name of its own prefixed (see the module's documentation), line for line.
fn renamed(text: &str, declarations: &Declarations) -> String {
    let all = tokens(text);
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut previous = Token::Space("");
    // The brace depths at which the struct bodies the tokens are in began.
    let mut struct_bodies: Vec<usize> = Vec::new();
    let mut depth = 0usize;
    let mut struct_pending = false;
    for token in all {
        match token {
            Token::Other("{") => {
                depth += 1;
                if struct_pending {
                    struct_bodies.push(depth);
                    struct_pending = false;
                }
            }
            Token::Other("}") => {
                if struct_bodies.last() == Some(&depth) {
                    struct_bodies.pop();
                }
                depth = depth.saturating_sub(1);
            }
            Token::Other(";") => struct_pending = false,
            Token::Identifier("struct") => struct_pending = true,
            _ => {}
        }
        match token {
            Token::Identifier(name) => {
                let member = previous == Token::Other(".");
                let in_struct_body = !struct_bodies.is_empty() && !declarations.structs.contains(name);
                let glsl_own = is_builtin(name) && !declarations.redefined.contains(name);
                if member || in_struct_body || glsl_own {
                    out.push_str(name);
                } else {
                    out.push_str(PREFIX);
                    out.push_str(name);
                }
            }
            other => out.push_str(other.text()),
        }
        if token.is_significant() {
            previous = token;
        }
    }
    out
}

/// The most steps the loops of a model may take, all together, in one evaluation in the browser ([`guarded`]).
pub const WEBGL_MAX_LOOP_STEPS: u32 = 4096;

/// `text` (the file's shader, renamed) with every loop guarded: a `for`'s condition and a `while`'s (a
/// `do ... while` too) also call `analytic_guard()`, which counts the steps of one evaluation and stops every
/// loop past [`WEBGL_MAX_LOOP_STEPS`], setting `analytic_stopped` (common/analytic.glsl). For the browser: a
/// WebGL2 loop that never ends hangs the GPU process (SwiftShader's, Chromium's: a dead tab, and every other
/// page that draws), and GLSL ES has no other way to run forever (it has no recursion). Lines stay lines.
fn guarded(text: &str) -> String {
    let all = tokens(text);
    let mut out = String::with_capacity(text.len() + 64);
    let mut k = 0;
    while k < all.len() {
        let token = all[k];
        out.push_str(token.text());
        k += 1;
        let Token::Identifier(keyword @ ("for" | "while")) = token else { continue };
        // The parenthesis that opens the loop's header, after any space or comment.
        let Some(open) = (k..all.len()).find(|&j| all[j].is_significant()) else { continue };
        if all[open] != Token::Other("(") {
            continue;
        }
        let mut depth = 0;
        let mut close = None;
        let mut semicolons = Vec::new();
        for (j, token) in all.iter().enumerate().skip(open) {
            match token {
                Token::Other("(") => depth += 1,
                Token::Other(")") => {
                    depth -= 1;
                    if depth == 0 {
                        close = Some(j);
                        break;
                    }
                }
                Token::Other(";") if depth == 1 => semicolons.push(j),
                _ => {}
            }
        }
        let Some(close) = close else { continue };
        let text_of = |range: std::ops::Range<usize>| all[range].iter().map(|t| t.text()).collect::<String>();
        out.push_str(&text_of(k..open + 1));
        let condition = match (keyword, semicolons.as_slice()) {
            ("while", []) => open + 1..close,
            ("for", [first, second]) => {
                out.push_str(&text_of(open + 1..first + 1));
                first + 1..*second
            }
            _ => {
                k = open + 1;
                continue;
            }
        };
        let written = text_of(condition.clone());
        if all[condition.clone()].iter().any(|t| t.is_significant()) {
            out.push_str(&format!("({written}) && analytic_guard()"));
        } else {
            out.push_str(&format!("{written}analytic_guard()"));
        }
        out.push_str(&text_of(condition.end..close + 1));
        k = close + 1;
    }
    out
}

/// The GLSL of one model: `brdf/analytic.glsl` as the shaders include it (brdf.glsl, under ANALYTIC_BRDF):
/// the parameters as globals, the file's shader then its isFunc section (`sampler`, the model's importance
/// sampler, empty when it has none) line for line at their own lines, `analytic_brdf(first, n, t, wi, wo)`,
/// which sets the parameters from `analytic_parameter(first + k)` (of the values common/analytic.glsl
/// declares) and calls the file's BRDF with X = t, Y = n x t; and with a sampler, ANALYTIC_HAS_SAMPLER
/// defined, `analytic_sample(first, n, t, wo, u)` and `analytic_pdf(first, n, t, wi, wo)` likewise.
///
/// # Errors
/// A [`ParseError`] when the shader defines no `vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`, or the isFunc
/// section no `vec3 sampleBRDF(vec3 V, vec3 N, vec3 X, vec3 Y, vec2 u)` and `float pdfBRDF(vec3 L, vec3 V, vec3 N,
/// vec3 X, vec3 Y)`, or one of them has other types.
pub fn wrap(
    parameters: &[Parameter],
    shader: &[(usize, String)],
    sampler: &[(usize, String)],
    target: Target,
) -> Result<String, ParseError> {
    wrap_in(parameters, shader, sampler, target, Precision::Single)
}

/// The same model with every float of the file's a double, for the renderer's `brdf_density64.comp`: the
/// file's `float`, `vecN` and `matN` made `double`, `dvecN` and `dmatN`, its floating literals double ones
/// (`0.1` would round to float first), and the functions GLSL has in float alone (`exp`, `pow`, `sin`, ...)
/// those of `shaders/common/float64.glsl`; the wrapper's functions take and return doubles. A file whose
/// GLSL does not compile so (one that reinterprets a float's bits) has no double evaluation.
///
/// # Errors
/// As [`wrap`].
pub fn wrap_double(
    parameters: &[Parameter],
    shader: &[(usize, String)],
    sampler: &[(usize, String)],
) -> Result<String, ParseError> {
    wrap_in(parameters, shader, sampler, Target::Vulkan, Precision::Double)
}

/// Where a shader file of vk-render's made double ([`shader_in_double`]) is found: `double/` before its path
/// (`double/brdf/cook_torrance.glsl`), as the shader compiler and build.rs both offer it.
pub const DOUBLE_FOLDER: &str = "double/";

/// The files a double shader includes as they are: the layouts it shares with the float code that fills its
/// buffers (the material), and the double functions themselves.
const INCLUDED_AS_THEY_ARE: [&str; 2] = ["common/material.glsl", "common/float64.glsl"];

/// The file a line `#include "FILE"` names (relative to shaders/), and what follows its closing quote; `None`
/// for any other line.
pub fn included_file(line: &str) -> Option<(&str, &str)> {
    line.trim_start().strip_prefix("#include \"")?.split_once('"')
}

/// One of vk-render's own shader files (shaders/`path`) with every float a double, as [`wrap_double`] makes a
/// `.brdf` file's: its types, literals and float-only functions, and each file it includes taken from
/// [`DOUBLE_FOLDER`] too (but the material's layout and float64.glsl, which it includes as they are). The
/// built-in models' integrals are made of it (`shaders/brdf_density64.comp`): the same GLSL as renders,
/// in double precision.
pub fn shader_in_double(text: &str) -> String {
    let included: Vec<String> = text
        .split_inclusive('\n')
        .map(|line| match included_file(line) {
            Some((path, rest)) if !INCLUDED_AS_THEY_ARE.contains(&path) => {
                format!("#include \"{DOUBLE_FOLDER}{path}\"{rest}")
            }
            _ => line.to_string(),
        })
        .collect();
    in_double(&included.concat())
}

/// The precision a model's GLSL is evaluated in.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Precision {
    Single,
    Double,
}

impl Precision {
    /// The scalar, 2- and 3-vector types.
    fn types(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Precision::Single => ("float", "vec2", "vec3"),
            Precision::Double => ("double", "dvec2", "dvec3"),
        }
    }
}

/// GLSL's functions of float alone, which a double model calls as `f64_NAME` (shaders/common/float64.glsl).
const FLOAT_ONLY_FUNCTIONS: [&str; 19] = [
    "exp", "log", "pow", "exp2", "log2", "sin", "cos", "tan", "atan", "asin", "acos", "sinh", "cosh", "tanh", "asinh",
    "acosh", "atanh", "radians", "degrees",
];

/// `text` (a file's renamed GLSL) with its floats made doubles (see [`wrap_double`]).
fn in_double(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut previous = Token::Space("");
    for token in tokens(text) {
        // A struct's member keeps its name, as in `renamed`.
        let member = previous == Token::Other(".");
        if token.is_significant() {
            previous = token;
        }
        match token {
            Token::Identifier(name) if member => out.push_str(name),
            Token::Identifier(name) => match name {
                "float" => out.push_str("double"),
                _ if is_float_vector_or_matrix(name) => {
                    out.push('d');
                    out.push_str(name);
                }
                _ if FLOAT_ONLY_FUNCTIONS.contains(&name) => {
                    out.push_str("f64_");
                    out.push_str(name);
                }
                _ => out.push_str(name),
            },
            Token::Other(number) if is_floating_literal(number) => {
                out.push_str(number.trim_end_matches(['f', 'F']));
                out.push_str("LF");
            }
            other => out.push_str(other.text()),
        }
    }
    out
}

/// Whether `name` is a float vector or matrix type: vec2 to vec4, mat2 to mat4, matCxR.
fn is_float_vector_or_matrix(name: &str) -> bool {
    let size = |text: &str| matches!(text, "2" | "3" | "4");
    match (name.strip_prefix("vec"), name.strip_prefix("mat")) {
        (Some(n), _) => size(n),
        (_, Some(shape)) => shape.split_once('x').map_or(size(shape), |(c, r)| size(c) && size(r)),
        _ => false,
    }
}

/// Whether a token is a floating-point literal: digits with a point or an exponent, or a float suffix (not a
/// hexadecimal integer, whose digits may be e or f).
fn is_floating_literal(token: &str) -> bool {
    let starts_as_number = token.starts_with(|c: char| c.is_ascii_digit())
        || (token.starts_with('.') && token[1..].starts_with(|c: char| c.is_ascii_digit()));
    let hexadecimal = token.starts_with("0x") || token.starts_with("0X");
    let suffixed_double = token.ends_with("lf") || token.ends_with("LF");
    starts_as_number
        && !hexadecimal
        && !suffixed_double
        && (token.contains(['.', 'e', 'E']) || token.ends_with(['f', 'F']))
}

fn wrap_in(
    parameters: &[Parameter],
    shader: &[(usize, String)],
    sampler: &[(usize, String)],
    target: Target,
    precision: Precision,
) -> Result<String, ParseError> {
    let (float, vec2, vec3) = precision.types();
    let sections = || shader.iter().chain(sampler);
    let text: String = sections().map(|(_, line)| line.as_str()).collect::<Vec<_>>().join("\n");
    let lines: Vec<usize> = sections().map(|(number, _)| *number).collect();
    let all = tokens(&text);
    let required: &[&Signature] = if sampler.is_empty() { &[&BRDF] } else { &[&BRDF, &SAMPLE, &PDF] };
    let declarations = declarations(&significant(&all), &lines, required)?;
    let renamed = match (target, precision) {
        (Target::Vulkan, Precision::Single) => renamed(&text, &declarations),
        (Target::Vulkan, Precision::Double) => in_double(&renamed(&text, &declarations)),
        (Target::WebGl, _) => guarded(&renamed(&text, &declarations)),
    };
    let mut glsl = String::from(
        "// The analytic BRDF of one .brdf file, made by vk-render (crates/brdf-file/src/glsl.rs): its parameters, then \
         its\n// shader with its own names prefixed, each line at its line in the file.\n#ifndef BRDF_ANALYTIC_GLSL\n\
         #define BRDF_ANALYTIC_GLSL\n",
    );
    if target == Target::WebGl {
        // SPIRV-Cross's GLSL ES says `precision mediump float` and qualifies its own declarations: the file's
        // are highp, as they are in the renderer (a phone's GPU would take mediump for 16 bits).
        glsl.push_str("precision highp float;\nprecision highp int;\n");
    }
    for parameter in parameters {
        let kind = match parameter.kind {
            ParameterKind::Float { .. } => float,
            ParameterKind::Bool { .. } => "bool",
            ParameterKind::Color { .. } => vec3,
        };
        glsl.push_str(&format!("{kind} {PREFIX}{};\n", parameter.name));
    }
    if target == Target::WebGl {
        glsl.push_str(&format!(
            "int analytic_steps;\nbool analytic_guard() {{\n    analytic_steps += 1;\n    analytic_stopped = \
             analytic_stopped || analytic_steps > {WEBGL_MAX_LOOP_STEPS};\n    return !analytic_stopped;\n}}\n"
        ));
    }
    let mut expected = None;
    for (number, line) in lines.iter().zip(renamed.split('\n')) {
        if expected != Some(*number) {
            glsl.push_str(&target.file_line(*number));
        }
        glsl.push_str(line);
        glsl.push('\n');
        expected = Some(number + 1);
    }
    glsl.push_str(&target.wrapper_lines());
    glsl.push_str("void analytic_set_parameters(uint first) {\n");
    let mut offset = 0;
    for parameter in parameters {
        let value = |k: usize| format!("analytic_parameter(first + {}u)", offset + k);
        let name = &parameter.name;
        match parameter.kind {
            ParameterKind::Float { .. } => glsl.push_str(&format!("    {PREFIX}{name} = {};\n", value(0))),
            ParameterKind::Bool { .. } => glsl.push_str(&format!("    {PREFIX}{name} = {} != 0.0;\n", value(0))),
            ParameterKind::Color { .. } => {
                glsl.push_str(&format!("    {PREFIX}{name} = {vec3}({}, {}, {});\n", value(0), value(1), value(2)));
            }
        }
        offset += parameter.kind.floats();
    }
    glsl.push_str(&format!(
        "}}\n{vec3} analytic_brdf(uint first, {vec3} n, {vec3} t, {vec3} wi, {vec3} wo) {{\n    \
         analytic_set_parameters(first);\n"
    ));
    match target {
        Target::Vulkan => glsl.push_str(&format!("    return {PREFIX}BRDF(wi, wo, n, t, cross(n, t));\n}}\n")),
        // A model stopped by its loops' guard gives 0 (and the page says so: analytic_stopped).
        Target::WebGl => glsl.push_str(&format!(
            "    analytic_steps = 0;\n    analytic_stopped = false;\n    vec3 f = {PREFIX}BRDF(wi, wo, n, t, cross(n, \
             t));\n    return analytic_stopped ? vec3(0.0) : f;\n}}\n"
        )),
    }
    if !sampler.is_empty() {
        glsl.push_str(&format!(
            "#define ANALYTIC_HAS_SAMPLER\n{vec3} analytic_sample(uint first, {vec3} n, {vec3} t, {vec3} wo, {vec2} u) \
             {{\n    analytic_set_parameters(first);\n    return {PREFIX}sampleBRDF(wo, n, t, cross(n, t), u);\n}}\n\
             {float} analytic_pdf(uint first, {vec3} n, {vec3} t, {vec3} wi, {vec3} wo) {{\n    \
             analytic_set_parameters(first);\n    return {PREFIX}pdfBRDF(wi, wo, n, t, cross(n, t));\n}}\n"
        ));
    }
    glsl.push_str("#endif\n");
    Ok(glsl)
}

/// The translation unit that checks a model's GLSL on its own when the file is loaded: the wrapper, the
/// parameter buffer it reads, and one call.
pub fn check_unit(wrapper: &str) -> String {
    format!(
        "#version 460\nlayout(local_size_x = 1) in;\nlayout(set = 0, binding = 0, std430) readonly buffer \
         AnalyticParameters {{ float analytic_parameters[]; }};\nfloat analytic_parameter(uint k) {{ return \
         analytic_parameters[k]; }}\nlayout(set = 0, binding = 1, std430) writeonly \
         buffer Result {{ vec4 result; }};\n{wrapper}void main() {{\n    result = vec4(analytic_brdf(0u, vec3(0.0, \
         0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0)), 0.0);\n}}\n"
    )
}

/// The compiler's first error in `log` as one line of the file's own: `LINE: message`, the file's names
/// without their prefix (the line is `None` for an error outside the file's lines, which would be vk-render's).
/// glslang (`target` Vulkan) writes `BRDF_FILE:12: error: ...`; WebGL2's compilers (ANGLE, SwiftShader) write
/// `ERROR: 1:12: ...`, 1 being the file's source string.
pub fn file_error(log: &str, target: Target) -> ParseError {
    let (error_mark, file_mark) = match target {
        Target::Vulkan => (": error:".to_string(), format!("{LINE_FILE}:")),
        Target::WebGl => ("ERROR:".to_string(), format!("ERROR: {ES_FILE}:")),
    };
    let first = log.lines().find(|line| line.contains(&error_mark)).unwrap_or(log).trim();
    let unprefixed = without_prefix(first);
    match unprefixed.find(&file_mark) {
        Some(at) => {
            let rest = &unprefixed[at + file_mark.len()..];
            let (line, message) = rest.split_once(':').unwrap_or(("", rest));
            let message = message.trim().trim_start_matches("error:").trim();
            ParseError { line: line.trim().parse().ok(), message: format!("GLSL: {message}") }
        }
        None => {
            let message =
                match target {
                    Target::Vulkan => unprefixed,
                    Target::WebGl => unprefixed
                        .replacen(&format!("ERROR: {ES_TEMPLATE}:"), "ERROR: line ", 1)
                        .replacen(&format!("ERROR: {ES_WRAPPER}:"), "ERROR: line ", 1),
                };
            ParseError { line: None, message: format!("GLSL, in vk-render's wrapper of the file: {message}") }
        }
    }
}

/// `text` with [`PREFIX`] taken off every identifier that starts with it.
fn without_prefix(text: &str) -> String {
    tokens(text)
        .into_iter()
        .map(|token| match token {
            Token::Identifier(name) => name.strip_prefix(PREFIX).unwrap_or(name),
            other => other.text(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rename(text: &str) -> String {
        let all = tokens(text);
        let lines: Vec<usize> = (1..=text.lines().count()).collect();
        let declarations = declarations(&significant(&all), &lines, &[&BRDF]).unwrap();
        renamed(text, &declarations)
    }

    const BRDF_TEXT: &str = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(1.0); }";

    #[test]
    fn the_files_names_are_prefixed_and_glsls_are_kept() {
        let text = format!(
            "const float PI = 3.14159265;\nfloat sqr(float x) {{ return x*x; }}\n{BRDF_TEXT}\nfloat G(vec3 h) {{ return \
             pow(max(0, dot(h.xyz, h)), 2e-3) * h.x + .5e+2 + 1.0f; }}"
        );
        let renamed = rename(&text);
        assert!(renamed.contains("const float usr_PI = 3.14159265;"), "{renamed}");
        assert!(renamed.contains("float usr_sqr(float usr_x) { return usr_x*usr_x; }"), "{renamed}");
        assert!(renamed.contains("vec3 usr_BRDF(vec3 usr_L, vec3 usr_V,"), "{renamed}");
        assert!(
            renamed.contains(
                "float usr_G(vec3 usr_h) { return pow(max(0, dot(usr_h.xyz, usr_h)), 2e-3) * usr_h.x + .5e+2 + 1.0f; }"
            ),
            "{renamed}"
        );
        assert_eq!(renamed.lines().count(), text.lines().count());
    }

    #[test]
    fn a_redefined_builtin_is_prefixed_calls_and_all() {
        let text = format!(
            "vec3 reflect(vec3 I, vec3 N)\n{{\n    return 2*dot(I,N)*N - I;\n}}\n{BRDF_TEXT}\nvec3 r(vec3 a) {{ return \
             reflect(a, a) + refract(a, a, 1.0); }}"
        );
        let renamed = rename(&text);
        assert!(renamed.starts_with("vec3 usr_reflect(vec3 usr_I, vec3 usr_N)"), "{renamed}");
        assert!(renamed.contains("return usr_reflect(usr_a, usr_a) + refract(usr_a, usr_a, 1.0);"), "{renamed}");
        // A call at global scope (an initializer) is not a definition.
        let initializer = rename(&format!("const float s = sqrt(2.0);\n{BRDF_TEXT}"));
        assert!(initializer.contains("const float usr_s = sqrt(2.0);"), "{initializer}");
    }

    #[test]
    fn struct_members_keep_their_names_and_struct_types_are_prefixed() {
        let text =
            format!("struct Lobe {{ float n; vec3 c; }};\nLobe make() {{ Lobe l; l.n = 1.0; return l; }}\n{BRDF_TEXT}");
        let renamed = rename(&text);
        assert!(renamed.starts_with("struct usr_Lobe { float n; vec3 c; };"), "{renamed}");
        assert!(renamed.contains("usr_Lobe usr_make() { usr_Lobe usr_l; usr_l.n = 1.0; return usr_l; }"), "{renamed}");
    }

    #[test]
    fn comments_are_kept_as_written_and_lines_stay_lines() {
        let text = format!("/* PI\n sqr */ float a; // G\n{BRDF_TEXT}");
        let renamed = rename(&text);
        assert!(renamed.starts_with("/* PI\n sqr */ float usr_a; // G\n"), "{renamed}");
    }

    #[test]
    fn the_brdf_function_must_have_vk_renders_signature() {
        let check = |text: &str| {
            let all = tokens(text);
            declarations(&significant(&all), &[7, 8, 9], &[&BRDF]).err()
        };
        assert!(check(BRDF_TEXT).is_none());
        assert!(check("vec3 BRDF(in vec3 L, const vec3 V, vec3 N, vec3 X, highp vec3 Y)\n{ return L; }").is_none());
        let float = check("float BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return 1.0; }").unwrap();
        assert_eq!(float.line, Some(7));
        assert!(float.message.contains("defines `float BRDF(vec3, vec3, vec3, vec3, vec3)`"), "{}", float.message);
        let three = check("\nvec3 BRDF(vec3 L, vec3 V, vec3 N) { return L; }").unwrap();
        assert_eq!(three.line, Some(8));
        assert!(three.message.contains("`vec3 BRDF(vec3, vec3, vec3)`"), "{}", three.message);
        let none = check("vec3 brdf(vec3 L) { return L; }").unwrap();
        assert_eq!(none.line, None);
        assert!(none.message.contains("defines no function `vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`"));
        let prototype = check("vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y);").unwrap();
        assert!(prototype.message.contains("defines no function"), "{}", prototype.message);
    }

    #[test]
    fn a_sampler_needs_both_functions_with_vk_renders_signatures() {
        let sample = "vec3 sampleBRDF(vec3 V, vec3 N, vec3 X, vec3 Y, vec2 u) { return N; }";
        let pdf = "float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return 1.0; }";
        let check = |text: &str| {
            let all = tokens(text);
            let lines: Vec<usize> = (20..40).collect();
            declarations(&significant(&all), &lines, &[&BRDF, &SAMPLE, &PDF]).err()
        };
        assert!(check(&format!("{BRDF_TEXT}\n{sample}\n{pdf}")).is_none());
        let missing = check(&format!("{BRDF_TEXT}\n{sample}")).unwrap();
        assert_eq!(missing.line, None);
        assert_eq!(
            missing.message,
            "the isFunc section defines no function `float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`"
        );
        let mistyped =
            check(&format!("{BRDF_TEXT}\n{pdf}\nvec3 sampleBRDF(vec3 V, vec3 N, vec2 u) {{ return N; }}")).unwrap();
        assert_eq!(mistyped.line, Some(22));
        assert!(mistyped.message.starts_with("the isFunc section defines `vec3 sampleBRDF(vec3, vec3, vec2)`"));
        // The wrapper calls them with the frame and sets the parameters first; a file without a sampler
        // has neither.
        let shader = [(5, BRDF_TEXT.to_string())];
        let wrapped = wrap(&[], &shader, &[(9, sample.to_string()), (10, pdf.to_string())], Target::Vulkan).unwrap();
        assert!(wrapped.contains("#define ANALYTIC_HAS_SAMPLER"), "{wrapped}");
        assert!(wrapped.contains("return usr_sampleBRDF(wo, n, t, cross(n, t), u);"), "{wrapped}");
        assert!(wrapped.contains("return usr_pdfBRDF(wi, wo, n, t, cross(n, t));"), "{wrapped}");
        assert!(!wrap(&[], &shader, &[], Target::Vulkan).unwrap().contains("ANALYTIC_HAS_SAMPLER"));
    }

    #[test]
    fn compiler_messages_name_the_files_line_and_names() {
        let log = "forward.frag:3: warning: something\nBRDF_FILE:12: error: 'usr_foo' : undeclared identifier\n\
                   BRDF_FILE:13: error: 'usr_bar' : no such\n2 errors generated.";
        let e = file_error(log, Target::Vulkan);
        assert_eq!(e.line, Some(12));
        assert_eq!(e.message, "GLSL: 'foo' : undeclared identifier");
        let wrapper = file_error("brdf/analytic.glsl:2: error: 'usr_x' : bad", Target::Vulkan);
        assert_eq!(wrapper.line, None);
        assert!(wrapper.message.contains("'x' : bad"), "{}", wrapper.message);
    }

    #[test]
    fn the_browsers_text_numbers_lines_by_source_string_and_its_messages_are_read_back() {
        let shader = [(5, BRDF_TEXT.to_string()), (7, "// last".to_string())];
        let parameters =
            [Parameter { name: "a".into(), kind: ParameterKind::Float { min: 0.0, max: 1.0, default: 0.5 }, line: 3 }];
        let wrapped = wrap(&parameters, &shader, &[], Target::WebGl).unwrap();
        assert!(wrapped.contains("#line 5 1\nvec3 usr_BRDF("), "{wrapped}");
        assert!(wrapped.contains("#line 7 1\n// last\n#line 1 2\nvoid analytic_set_parameters"), "{wrapped}");
        assert!(wrapped.contains("usr_a = analytic_parameter(first + 0u);"), "{wrapped}");
        assert!(!wrapped.contains('"'), "GLSL ES has no strings: {wrapped}");
        assert!(wrapped.contains("precision highp float;\n"), "{wrapped}");
        let log = "WARNING: 0:3: something\nERROR: 1:12: 'usr_foo' : undeclared identifier\n\
                   ERROR: 1:12: '' : compilation terminated\n2 compilation errors.  No code generated.";
        let e = file_error(log, Target::WebGl);
        assert_eq!(e.line, Some(12));
        assert_eq!(e.message, "GLSL: 'foo' : undeclared identifier");
        let template = file_error("ERROR: 0:300: 'x' : bad", Target::WebGl);
        assert_eq!(template.line, None);
        assert!(template.message.contains("wrapper of the file: ERROR: line 300: 'x' : bad"), "{}", template.message);
    }

    #[test]
    fn the_browsers_loops_are_guarded_line_for_line() {
        let text = "for (int i = 0; i < n; i++) x += 1.0;\nwhile (a\n > b) { for (;;) {} }\ndo { y(); } while (c);\n\
                    float fortune(float while_) { return (while_); }";
        let out = guarded(text);
        assert_eq!(
            out,
            "for (int i = 0;( i < n) && analytic_guard(); i++) x += 1.0;\nwhile ((a\n > b) && analytic_guard()) { for \
             (;analytic_guard();) {} }\ndo { y(); } while ((c) && analytic_guard());\nfloat fortune(float while_) { \
             return (while_); }"
        );
        assert_eq!(out.lines().count(), text.lines().count());
        let shader =
            [(5, "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { while (true) {} return L; }".to_string())];
        let webgl = wrap(&[], &shader, &[], Target::WebGl).unwrap();
        assert!(webgl.contains("while ((true) && analytic_guard())"), "{webgl}");
        assert!(webgl.contains("analytic_steps > 4096"), "{webgl}");
        assert!(webgl.contains("return analytic_stopped ? vec3(0.0) : f;"), "{webgl}");
        let vulkan = wrap(&[], &shader, &[], Target::Vulkan).unwrap();
        assert!(vulkan.contains("while (true) {}") && !vulkan.contains("analytic_guard"), "{vulkan}");
    }

    #[test]
    fn a_shader_in_double_includes_double_files_but_the_shared_layouts() {
        let glsl = shader_in_double(
            "#include \"common/material.glsl\"\n#include \"brdf/lambert.glsl\"\n  #include \"common/math.glsl\"  // PI\n\
             vec3 lambert(vec3 kd) { return kd * INV_PI; }\n",
        );
        assert_eq!(
            glsl,
            "#include \"common/material.glsl\"\n#include \"double/brdf/lambert.glsl\"\n#include \
             \"double/common/math.glsl\"  // PI\ndvec3 lambert(dvec3 kd) { return kd * INV_PI; }\n"
        );
    }

    #[test]
    fn a_double_model_has_double_types_literals_and_functions() {
        let glsl = in_double(
            "const float usr_PI = 3.14159265358979323846;\nvec3 usr_f(vec2 u, mat3 m, mat2x3 n) {\n    float a = \
             pow(u.x, 5.0) + exp(-1e-3) + 2.5f + .5 + 1.0E+2 + 0x1F + 3u + 7 + s.exp + s.mat;\n    return vec3(sin(a), u.y, \
             float(2));\n}",
        );
        assert_eq!(
            glsl,
            "const double usr_PI = 3.14159265358979323846LF;\ndvec3 usr_f(dvec2 u, dmat3 m, dmat2x3 n) {\n    double a \
             = f64_pow(u.x, 5.0LF) + f64_exp(-1e-3LF) + 2.5LF + .5LF + 1.0E+2LF + 0x1F + 3u + 7 + s.exp + s.mat;\n    \
             return dvec3(f64_sin(a), u.y, double(2));\n}"
        );
    }
}
