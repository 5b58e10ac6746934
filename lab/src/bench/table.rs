//! A small result table that prints as CSV and as markdown.

/// Named columns of pre-formatted cells.
#[derive(Clone, Debug)]
pub struct Table {
    /// File stem of the CSV and heading of the markdown table.
    pub name: String,
    pub title: String,
    pub columns: Vec<&'static str>,
    pub rows: Vec<Vec<String>>,
    /// A line printed under the markdown table.
    pub note: String,
}

impl Table {
    pub fn new(name: &str, title: &str, columns: &[&'static str]) -> Self {
        Self {
            name: name.into(),
            title: title.into(),
            columns: columns.to_vec(),
            rows: Vec::new(),
            note: String::new(),
        }
    }

    pub fn push(&mut self, row: Vec<String>) {
        debug_assert_eq!(row.len(), self.columns.len());
        self.rows.push(row);
    }

    /// RFC 4180 CSV: a cell with a comma, quote or line break is quoted.
    pub fn csv(&self) -> String {
        let mut s = self.columns.join(",");
        s.push('\n');
        for row in &self.rows {
            let cells: Vec<String> = row.iter().map(|c| csv_cell(c)).collect();
            s.push_str(&cells.join(","));
            s.push('\n');
        }
        s
    }

    pub fn markdown(&self) -> String {
        let mut s = format!("## {}\n\n| {} |\n|", self.title, self.columns.join(" | "));
        s.push_str(&"---|".repeat(self.columns.len()));
        s.push('\n');
        for row in &self.rows {
            s.push_str(&format!("| {} |\n", row.join(" | ")));
        }
        if !self.note.is_empty() {
            s.push_str(&format!("\n{}\n", self.note));
        }
        s
    }
}

fn csv_cell(c: &str) -> String {
    if c.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", c.replace('"', "\"\""))
    } else {
        c.to_string()
    }
}

/// A number in short scientific notation, as the tables print errors.
pub fn sci(v: f64) -> String {
    format!("{v:.2e}")
}
