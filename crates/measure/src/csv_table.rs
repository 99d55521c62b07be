//! The CSV files the measurements write: a header and rows of fields already formatted,
//! quoted where a field needs it (RFC 4180: a scene path with a comma stays one field), by the
//! csv crate. A row of another length than the header is an error, not a shifted column.

use std::path::Path;

use leakless::{RenderError, Result};

/// One CSV table being written.
pub struct CsvTable {
    writer: csv::Writer<Vec<u8>>,
    columns: usize,
}

impl CsvTable {
    pub fn new(header: &[&str]) -> CsvTable {
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer.write_record(header).expect("writing to memory");
        CsvTable { writer, columns: header.len() }
    }

    /// Adds a row; its fields must be as many as the header's.
    pub fn row<S: AsRef<str>>(&mut self, fields: impl IntoIterator<Item = S>) -> Result<()> {
        let fields: Vec<String> = fields.into_iter().map(|f| f.as_ref().to_string()).collect();
        if fields.len() != self.columns {
            return Err(RenderError::Settings(format!(
                "a CSV row of {} fields under a header of {}: {fields:?}",
                fields.len(),
                self.columns
            )));
        }
        self.writer.write_record(&fields).map_err(|e| RenderError::Settings(format!("writing a CSV row: {e}")))
    }

    /// The table as text.
    pub fn text(self) -> String {
        let bytes = self.writer.into_inner().expect("writing to memory");
        String::from_utf8(bytes).expect("the fields were text")
    }

    /// Writes the table to `path`.
    pub fn write(self, path: &Path) -> Result<()> {
        std::fs::write(path, self.text())
            .map_err(|e| RenderError::Output { path: path.display().to_string(), message: e.to_string() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field with a comma or a quote is quoted, and a short row is refused.
    #[test]
    fn fields_are_quoted_and_rows_are_whole() {
        let mut t = CsvTable::new(&["scene", "ms"]);
        t.row(["scenes/a,b.gltf", "1.5"]).unwrap();
        t.row(["say \"hi\"", "2"]).unwrap();
        assert!(t.row(["short"]).is_err());
        assert_eq!(t.text(), "scene,ms\n\"scenes/a,b.gltf\",1.5\n\"say \"\"hi\"\"\",2\n");
    }
}
