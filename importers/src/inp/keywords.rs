//! Keyword lines: parsed, abbreviations expanded, the current data block ended, and the
//! keyword dispatched; data lines dispatched by the current [`Mode`].

use super::lex;
use super::{Include, Mode, Reader};
use crate::error::{describe_found, ImportError};

impl Reader {
    pub(super) fn keyword(
        &mut self,
        text: &[u8],
        file: u32,
        line: usize,
    ) -> Result<Option<Include>, ImportError> {
        let kw = match lex::keyword(text) {
            Ok(k) => k,
            Err((at, expected)) => {
                let name_end = text.iter().position(|&b| b == b',').unwrap_or(text.len());
                let name: String = text[1..name_end]
                    .iter()
                    .filter(|b| !b.is_ascii_whitespace())
                    .map(|b| b.to_ascii_uppercase() as char)
                    .collect();
                if MODELLED.contains(&name.as_str()) {
                    return Err(self.err(
                        file,
                        line,
                        expected,
                        describe_found(&text[at.min(text.len())..]),
                    ));
                }
                self.end_block(file, line, text)?;
                self.mode = Mode::Skip;
                return Ok(None);
            }
        };
        let mut kw = kw;
        if let Some(full) = self.expand_abbreviation(&kw.name, file, line)? {
            kw.name = full.to_string();
        }
        if kw.name == "INCLUDE" {
            // The included lines stand in place of this line: the current block goes on.
            let target = self.required(&kw, "INPUT", file, line, text)?;
            return Ok(Some(Include { target }));
        }
        self.end_block(file, line, text)?;
        self.mode = Mode::Skip;
        let name = kw.name.clone();
        match name.as_str() {
            "NODE" => self.kw_node(&kw, file, line, text)?,
            "ELEMENT" => self.kw_element(&kw, file, line, text)?,
            "NSET" | "ELSET" => self.kw_set(&kw, name == "ELSET", file, line, text)?,
            "PART" => self.kw_part(&kw, file, line, text)?,
            "ENDPART" => self.kw_end_part(file, line, text)?,
            "ASSEMBLY" => self.kw_assembly(&kw, file, line, text)?,
            "ENDASSEMBLY" => self.kw_end_assembly(file, line, text)?,
            "INSTANCE" => self.kw_instance(&kw, file, line, text)?,
            "ENDINSTANCE" => self.kw_end_instance(file, line, text)?,
            "SYSTEM" => {
                self.system = None;
                self.system_points.clear();
                self.mode = Mode::System { lines: 0 };
            }
            "NGEN" | "NFILL" | "NCOPY" | "NMAP" | "ELGEN" | "ELCOPY" => {
                return Err(self.err(
                    file,
                    line,
                    "nodes and elements listed one by one (mesh generation keywords are not supported)",
                    describe_found(text),
                ));
            }
            _ => {}
        }
        // `INPUT=` on a data keyword: its data lines come from that file.
        if matches!(name.as_str(), "NODE" | "ELEMENT" | "NSET" | "ELSET") {
            if let Some(input) = kw.value("INPUT") {
                return Ok(Some(Include {
                    target: input.to_string(),
                }));
            }
        }
        Ok(None)
    }

    /// The keyword this reader acts on that `name` abbreviates, if it is one: Abaqus accepts
    /// unambiguous abbreviations (FORMATS.md §3.1), such as `*ELEM` for `*ELEMENT`. An
    /// abbreviation of one of them that could also stand for another Abaqus keyword (`*NOD`:
    /// `*NODE` or `*NODAL THICKNESS`) is an error rather than a guess, since skipping it would
    /// drop its data.
    fn expand_abbreviation(
        &mut self,
        name: &str,
        file: u32,
        line: usize,
    ) -> Result<Option<&'static str>, ImportError> {
        if name.len() < 3 || ACTED_ON.contains(&name) {
            return Ok(None);
        }
        // (written form, blanks removed)
        let mut candidates: Vec<(&str, String)> = ACTED_ON
            .iter()
            .chain(LOOK_ALIKES.iter())
            .map(|k| (*k, k.replace(' ', "")))
            .filter(|(_, k)| k.starts_with(name))
            .collect();
        let Some(&(first, _)) = candidates.first() else {
            return Ok(None);
        };
        if !ACTED_ON.contains(&first) {
            return Ok(None);
        }
        // `*ELEM` also begins `*ELEMENT OUTPUT` and the like, which begin with `*ELEMENT`.
        candidates.retain(|(_, k)| !(k.starts_with(first) && k != first));
        if candidates.len() > 1 {
            let names: Vec<String> = candidates.iter().map(|(k, _)| format!("*{k}")).collect();
            return Err(self.err(
                file,
                line,
                format!("a keyword written out in full ({})", names.join(" or ")),
                format!("*{name}, an abbreviation of more than one keyword"),
            ));
        }
        let full = first;
        let shown = if file == 0 {
            format!("line {line}")
        } else {
            format!("{}:{line}", self.files[file as usize].display())
        };
        self.warn(format!("{shown}: *{name} read as *{full}"));
        Ok(Some(full))
    }

    /// Ends the current data block before a keyword line: an unfinished element record is an
    /// error (unless its type's node count is unknown), `*SYSTEM` data takes effect.
    fn end_block(&mut self, file: u32, line: usize, text: &[u8]) -> Result<(), ImportError> {
        if self.pending.is_some() && self.pending_need().is_none() {
            // A record of a type with unknown node count ended with a trailing comma.
            if let Mode::Element { unit, ty, set } = self.mode {
                self.finish_element(unit, ty, set)?;
            }
        }
        if let Some(e) = self.overlong_record() {
            // A record that ended with a trailing comma after more node numbers than its type
            // has.
            return Err(e);
        }
        if let Some(p) = self.pending.take() {
            let need = self.pending_need().unwrap_or(0);
            return Err(self.err(
                file,
                line,
                format!(
                    "{} more node numbers of element {} (record started at {})",
                    need.saturating_sub(self.tokens.len()),
                    p.label,
                    if p.file == file {
                        format!("line {}", p.line)
                    } else {
                        format!("{}:{}", self.files[p.file as usize].display(), p.line)
                    }
                ),
                describe_found(text),
            ));
        }
        if let Mode::System { .. } = self.mode {
            self.finish_system(file, line)?;
        }
        Ok(())
    }

    pub(super) fn data_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
    ) -> Result<(), ImportError> {
        match self.mode {
            Mode::Start => Err(self.err(
                file,
                lineno,
                "a keyword line starting with '*' (or a '**' comment) first",
                describe_found(line),
            )),
            Mode::Skip => Ok(()),
            Mode::Node {
                unit,
                set,
                cylindrical,
            } => self.node_line(line, file, lineno, unit, set, cylindrical),
            Mode::Element { unit, ty, set } => self.element_line(line, file, lineno, unit, ty, set),
            Mode::Set { .. } => self.set_line(line, file, lineno),
            Mode::InstanceData { unit, lines } => {
                self.instance_line(line, file, lineno, unit, lines)
            }
            Mode::System { lines } => self.system_line(line, file, lineno, lines),
        }
    }
}

/// Keywords this reader acts on (reads, or refuses as unsupported).
const ACTED_ON: [&str; 18] = [
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "PART",
    "ENDPART",
    "ASSEMBLY",
    "ENDASSEMBLY",
    "INSTANCE",
    "ENDINSTANCE",
    "SYSTEM",
    "INCLUDE",
    "NGEN",
    "NFILL",
    "NCOPY",
    "NMAP",
    "ELGEN",
    "ELCOPY",
];

/// Other Abaqus keywords that begin with the same three or more letters as one in
/// [`ACTED_ON`]: an abbreviation (blanks removed) that begins one of these is ambiguous.
const LOOK_ALIKES: [&str; 14] = [
    "NODAL THICKNESS",
    "NODAL ENERGY RATE",
    "NODE OUTPUT",
    "NODE PRINT",
    "NODE FILE",
    "ELEMENT OUTPUT",
    "ELEMENT PROPERTIES",
    "ELECTRICAL CONDUCTIVITY",
    "PARAMETER",
    "ASSEMBLED FASTENER",
    "INCIDENT WAVE",
    "INCREMENTATION OUTPUT",
    "END STEP",
    "END LOAD CASE",
];

/// Keywords whose keyword lines must parse (others are skipped even when malformed).
const MODELLED: [&str; 12] = [
    "ENDPART",
    "ENDASSEMBLY",
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "INCLUDE",
    "PART",
    "ASSEMBLY",
    "INSTANCE",
    "SYSTEM",
    "ENDINSTANCE",
];
