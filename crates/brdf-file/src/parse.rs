//! BRDF Explorer's analytic file format, as its `BRDFBase::loadBRDF` reads it: the first word `analytic`; lines
//! trimmed, blank lines and lines starting with `#` skipped everywhere (inside the shader too); sections
//! `::begin NAME` ... `::end NAME` that do not nest; in `parameters`, one parameter a line.
//!
//! Where BRDF Explorer reads on silently (a parameter line it cannot read gives zeros), this reader stops
//! with the file and its line: a `.brdf` is a model someone will draw conclusions from.

use glam::Vec3;

use crate::names::is_keyword_or_type;
use crate::{Parameter, ParameterKind};

/// What a file holds, before its shader is checked and wrapped.
#[derive(Debug)]
pub struct BrdfFile {
    pub parameters: Vec<Parameter>,
    /// The shader section's lines as written, each with its line number in the file (from 1).
    pub shader: Vec<(usize, String)>,
    /// The isFunc section's lines (the model's importance sampler), likewise; empty when it has none.
    pub sampler: Vec<(usize, String)>,
    /// Lines that load but will not do what the file may mean, each naming its line.
    pub warnings: Vec<String>,
}

/// An error at one line of the file (from 1), or of the file as a whole.
#[derive(Debug, PartialEq)]
pub struct ParseError {
    pub line: Option<usize>,
    pub message: String,
}

fn at(line: usize, message: impl Into<String>) -> ParseError {
    ParseError { line: Some(line), message: message.into() }
}

/// Reads the text of a `.brdf` file.
pub fn parse(text: &str) -> Result<BrdfFile, ParseError> {
    let mut lines = text.lines().enumerate().map(|(i, line)| (i + 1, line));
    // BRDF Explorer takes the very first line as the type; a file that opens with a comment or a blank line
    // is read here too, as the rest of the file is.
    let first = lines.by_ref().find(|(_, line)| !skipped(line.trim()));
    let Some((first_number, first_line)) = first else {
        return Err(ParseError { line: None, message: "the file is empty: a BRDF file starts with `analytic`".into() });
    };
    let kind = first_line.split_whitespace().next().unwrap_or_default();
    if kind != "analytic" {
        return Err(at(
            first_number,
            format!(
                "the file starts with `{}`, not `analytic`: vk-render reads BRDF Explorer's analytic files (a \
                 `bparam` or measured file is not one)",
                crate::shortened(kind)
            ),
        ));
    }
    let mut file = BrdfFile { parameters: Vec::new(), shader: Vec::new(), sampler: Vec::new(), warnings: Vec::new() };
    let mut section: Option<(usize, String)> = None;
    let (mut shader_sections, mut sampler_sections) = (0, 0);
    for (number, line) in lines {
        let trimmed = line.trim();
        if skipped(trimmed) {
            if let Some(defined) = trimmed.strip_prefix('#').map(str::trim_start).filter(|d| d.starts_with("define")) {
                if section.as_ref().is_some_and(|(_, name)| name == "shader") {
                    file.warnings.push(format!(
                        "line {number}: `#{}` is dropped, as BRDF Explorer drops every line that starts with #: \
                         write it as a const instead",
                        crate::shortened(defined)
                    ));
                }
            }
            continue;
        }
        let mut words = trimmed.split_whitespace();
        match words.next() {
            Some("::begin") => {
                let name = words.next().ok_or_else(|| at(number, "`::begin` names no section"))?;
                if let Some((begun, open)) = &section {
                    return Err(at(
                        number,
                        format!(
                            "`::begin {name}` inside the section `{open}` begun at line {begun}: sections do not nest"
                        ),
                    ));
                }
                match name {
                    "parameters" => {}
                    "shader" => shader_sections += 1,
                    "isFunc" => sampler_sections += 1,
                    other => file.warnings.push(format!(
                        "line {number}: the section `{}` is not one vk-render reads (parameters, shader, isFunc): \
                         it is skipped",
                        crate::shortened(other)
                    )),
                }
                section = Some((number, name.to_string()));
            }
            Some("::end") => {
                let name = words.next().unwrap_or_default();
                match &section {
                    Some((_, open)) if open == name => section = None,
                    Some((begun, open)) => {
                        return Err(at(
                            number,
                            format!("`::end {name}` ends the section `{open}` begun at line {begun} (`::end {open}`)"),
                        ))
                    }
                    None => return Err(at(number, format!("`::end {name}` outside any section"))),
                }
            }
            _ => match section.as_ref().map(|(_, name)| name.as_str()) {
                Some("parameters") => {
                    let parameter = parameter(number, trimmed)?;
                    if let Some(earlier) = file.parameters.iter().find(|p| p.name == parameter.name) {
                        return Err(at(
                            number,
                            format!(
                                "the parameter `{}` is declared again (first at line {})",
                                parameter.name, earlier.line
                            ),
                        ));
                    }
                    file.parameters.push(parameter);
                }
                Some("shader") => file.shader.push((number, line.to_string())),
                Some("isFunc") => file.sampler.push((number, line.to_string())),
                Some(_) => {}
                None => {
                    return Err(at(
                        number,
                        format!(
                            "`{}` is outside any section (`::begin parameters`, `::begin shader`)",
                            crate::shortened(trimmed)
                        ),
                    ))
                }
            },
        }
    }
    if let Some((begun, open)) = section {
        return Err(at(begun, format!("the section `{open}` begun here is never ended (`::end {open}`)")));
    }
    if sampler_sections > 1 {
        return Err(ParseError { line: None, message: "the file has more than one isFunc section".into() });
    }
    match shader_sections {
        0 => Err(ParseError { line: None, message: "the file has no `::begin shader` section".into() }),
        1 => Ok(file),
        _ => Err(ParseError { line: None, message: "the file has more than one shader section".into() }),
    }
}

/// Whether BRDF Explorer skips a trimmed line: blank, or a comment.
fn skipped(trimmed: &str) -> bool {
    trimmed.is_empty() || trimmed.starts_with('#')
}

/// One line of the parameters section: `float NAME MIN MAX DEFAULT`, `bool NAME 0|1` or `color NAME R G B`.
fn parameter(number: usize, trimmed: &str) -> Result<Parameter, ParseError> {
    let words: Vec<&str> = trimmed.split_whitespace().collect();
    let (kind, rest) = words.split_first().map_or(("", &[][..]), |(k, rest)| (*k, rest));
    let form = match kind {
        "float" => "float NAME MIN MAX DEFAULT",
        "bool" => "bool NAME 0|1",
        "color" => "color NAME R G B",
        other => {
            return Err(at(
                number,
                format!("unknown parameter type `{}` (expected float, bool or color)", crate::shortened(other)),
            ))
        }
    };
    let expected = form.split_whitespace().count() - 1;
    if rest.len() != expected {
        return Err(at(number, format!("`{}`: a {kind} parameter is `{form}`", crate::shortened(trimmed))));
    }
    let name = identifier(number, rest[0])?;
    let number_at = |index: usize, what: &str| -> Result<f32, ParseError> {
        rest[index].parse::<f32>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
            at(number, format!("{kind} {name}: {what} `{}` is not a finite number", crate::shortened(rest[index])))
        })
    };
    let kind = match kind {
        "float" => {
            let (min, max, default) = (number_at(1, "MIN")?, number_at(2, "MAX")?, number_at(3, "DEFAULT")?);
            if min > max {
                return Err(at(number, format!("float {name}: MIN {min} is above MAX {max}")));
            }
            if !(min..=max).contains(&default) {
                return Err(at(number, format!("float {name}: DEFAULT {default} is outside [{min}, {max}]")));
            }
            ParameterKind::Float { min, max, default }
        }
        "bool" => match rest[1] {
            "0" => ParameterKind::Bool { default: false },
            "1" => ParameterKind::Bool { default: true },
            other => return Err(at(number, format!("bool {name}: `{}` is not 0 or 1", crate::shortened(other)))),
        },
        _ => ParameterKind::Color { default: Vec3::new(number_at(1, "R")?, number_at(2, "G")?, number_at(3, "B")?) },
    };
    Ok(Parameter { name, kind, line: number })
}

/// A parameter's name: a GLSL identifier that GLSL does not reserve (the shader reads it under that name).
fn identifier(number: usize, name: &str) -> Result<String, ParseError> {
    let mut chars = name.chars();
    let starts = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if !starts || !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(at(
            number,
            format!("`{}` is not a GLSL identifier (letters, digits and _)", crate::shortened(name)),
        ));
    }
    if is_keyword_or_type(name) {
        return Err(at(number, format!("the parameter name `{name}` is a GLSL keyword")));
    }
    if name.starts_with("gl_") || name.contains("__") {
        return Err(at(number, format!("the parameter name `{name}` is reserved by GLSL (gl_ and __)")));
    }
    Ok(name.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> ParseError {
        parse(text).unwrap_err()
    }

    const SHADER: &str =
        "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(1); }\n::end shader\n";

    #[test]
    fn a_file_reads_its_parameters_and_shader_lines_with_their_numbers() {
        let text = format!(
            "analytic\n# a comment\n\n::begin parameters\nfloat alpha_x 0 1.0 .15\n  bool isotropic 1\ncolor Cd 1 0.5 \
             0.25\n::end parameters\n{SHADER}"
        );
        let file = parse(&text).unwrap();
        assert_eq!(file.parameters.len(), 3);
        assert_eq!(file.parameters[0].name, "alpha_x");
        assert_eq!(file.parameters[0].kind, ParameterKind::Float { min: 0.0, max: 1.0, default: 0.15 });
        assert_eq!(file.parameters[0].line, 5);
        assert_eq!(file.parameters[1].kind, ParameterKind::Bool { default: true });
        assert_eq!(file.parameters[2].kind, ParameterKind::Color { default: Vec3::new(1.0, 0.5, 0.25) });
        assert_eq!(
            file.shader,
            vec![(10, "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(1); }".into())]
        );
        assert!(file.warnings.is_empty());
    }

    #[test]
    fn comments_and_defines_in_the_shader_are_dropped_and_a_define_is_warned_of() {
        let text = "analytic\n::begin shader\n#define K 2.0\n  # indented comment\nfloat k() { return 1.0; }\n\n::end shader\n";
        let file = parse(text).unwrap();
        assert_eq!(file.shader, vec![(5, "float k() { return 1.0; }".into())]);
        assert_eq!(file.warnings.len(), 1);
        assert!(file.warnings[0].starts_with("line 3: `#define K 2.0` is dropped"), "{}", file.warnings[0]);
    }

    #[test]
    fn an_isfunc_section_is_the_sampler_and_an_unknown_section_is_skipped_with_a_warning() {
        let text = format!(
            "analytic\n::begin isFunc\nvec3 sampleBRDF() {{}}\n::end isFunc\n::begin notes\nhi\n::end notes\n{SHADER}"
        );
        let file = parse(&text).unwrap();
        assert_eq!(file.shader.len(), 1);
        assert_eq!(file.sampler, vec![(3, "vec3 sampleBRDF() {}".into())]);
        assert_eq!(file.warnings.len(), 1, "{:?}", file.warnings);
        assert!(file.warnings[0].starts_with("line 5: the section `notes`"));
        let twice = format!("analytic\n::begin isFunc\n::end isFunc\n::begin isFunc\n::end isFunc\n{SHADER}");
        assert_eq!(parse(&twice).unwrap_err().message, "the file has more than one isFunc section");
    }

    #[test]
    fn every_malformed_file_is_named_at_its_line() {
        let cases: &[(&str, Option<usize>, &str)] = &[
            ("", None, "the file is empty"),
            ("bparam\n", Some(1), "starts with `bparam`, not `analytic`"),
            ("analytic\n::begin parameters\nint n 1 2 3\n::end parameters\n", Some(3), "unknown parameter type `int`"),
            ("analytic\n::begin parameters\nfloat n 2 1 1.5\n::end parameters\n", Some(3), "MIN 2 is above MAX 1"),
            ("analytic\n::begin parameters\nfloat n 0 1 3\n::end parameters\n", Some(3), "DEFAULT 3 is outside [0, 1]"),
            (
                "analytic\n::begin parameters\nfloat n 0 1\n::end parameters\n",
                Some(3),
                "is `float NAME MIN MAX DEFAULT`",
            ),
            ("analytic\n::begin parameters\nfloat n 0 one 1\n::end parameters\n", Some(3), "MAX `one` is not a finite"),
            ("analytic\n::begin parameters\nfloat n 0 inf 1\n::end parameters\n", Some(3), "MAX `inf` is not a finite"),
            ("analytic\n::begin parameters\nbool b true\n::end parameters\n", Some(3), "`true` is not 0 or 1"),
            ("analytic\n::begin parameters\ncolor c 1 1\n::end parameters\n", Some(3), "is `color NAME R G B`"),
            ("analytic\n::begin parameters\nfloat in 0 1 0\n::end parameters\n", Some(3), "`in` is a GLSL keyword"),
            ("analytic\n::begin parameters\nfloat vec3 0 1 0\n::end parameters\n", Some(3), "`vec3` is a GLSL keyword"),
            ("analytic\n::begin parameters\nfloat gl_x 0 1 0\n::end parameters\n", Some(3), "reserved by GLSL"),
            ("analytic\n::begin parameters\nfloat 2x 0 1 0\n::end parameters\n", Some(3), "not a GLSL identifier"),
            (
                "analytic\n::begin parameters\nfloat a 0 1 0\nbool a 0\n::end parameters\n",
                Some(4),
                "`a` is declared again (first at line 3)",
            ),
            ("analytic\n::begin shader\nfloat f;\n", Some(2), "never ended (`::end shader`)"),
            ("analytic\n::begin shader\n::begin parameters\n", Some(3), "inside the section `shader` begun at line 2"),
            ("analytic\n::begin shader\n::end parameters\n", Some(3), "ends the section `shader` begun at line 2"),
            ("analytic\n::end shader\n", Some(2), "outside any section"),
            ("analytic\nvec3 BRDF();\n", Some(2), "outside any section"),
            ("analytic\n::begin parameters\n::end parameters\n", None, "no `::begin shader` section"),
        ];
        for (text, line, expected) in cases {
            let e = error(text);
            assert_eq!(e.line, *line, "{text:?}: {e:?}");
            assert!(e.message.contains(expected), "{text:?}: {}", e.message);
        }
    }
}
