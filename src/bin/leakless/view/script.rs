//! Scripted runs (`--script FILE`): events replayed at frame numbers with a fixed time step,
//! for tests and benchmarks. One event per line (`#` starts a comment):
//!
//! ```text
//! FRAME key NAME          a winit key name (KeyW, Digit4, F12, ArrowUp...)
//! FRAME drag DX DY        a mouse drag of DX, DY pixels
//! FRAME resize W H        the window resized (0 0: minimised)
//! FRAME capture PATH.exr  a capture to PATH.exr (+ .png, .json)
//! FRAME quit
//! ```

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use winit::keyboard::KeyCode;

use super::keys;

#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    Key(KeyCode),
    Drag(f32, f32),
    Resize(u32, u32),
    Capture(PathBuf),
    Quit,
}

/// The events of a script, by frame.
#[derive(Clone, Debug, Default)]
pub struct Script {
    events: Vec<(u64, Event)>,
    next: usize,
}

impl Script {
    pub fn load(path: &Path) -> anyhow::Result<Script> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading script {}", path.display()))?;
        Script::parse(&text).with_context(|| format!("script {}", path.display()))
    }

    pub fn parse(text: &str) -> anyhow::Result<Script> {
        let mut events = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let event = parse_line(line).with_context(|| format!("line {}: {line:?}", n + 1))?;
            events.push(event);
        }
        // Stable: events of one frame keep their order.
        events.sort_by_key(|(frame, _)| *frame);
        Ok(Script { events, next: 0 })
    }

    /// The events of `frame` (call with increasing frames).
    pub fn take(&mut self, frame: u64) -> Vec<Event> {
        let mut out = Vec::new();
        while let Some((f, e)) = self.events.get(self.next) {
            if *f > frame {
                break;
            }
            out.push(e.clone());
            self.next += 1;
        }
        out
    }
}

fn parse_line(line: &str) -> anyhow::Result<(u64, Event)> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let frame: u64 = words[0].parse().with_context(|| format!("{:?} is not a frame number", words[0]))?;
    let number = |i: usize| -> anyhow::Result<f32> {
        let w = words.get(i).with_context(|| "missing a number")?;
        w.parse::<f32>().ok().filter(|v| v.is_finite()).with_context(|| format!("{w:?} is not a number"))
    };
    let size = |i: usize| -> anyhow::Result<u32> {
        let w = words.get(i).with_context(|| "missing a size")?;
        w.parse::<u32>().with_context(|| format!("{w:?} is not a size"))
    };
    let expect = |n: usize| -> anyhow::Result<()> {
        if words.len() != n {
            bail!("expected {} words, found {}", n, words.len());
        }
        Ok(())
    };
    let event = match words.get(1).copied() {
        Some("key") => {
            expect(3)?;
            Event::Key(keys::parse(words[2]).with_context(|| format!("{:?} is not a key the app uses", words[2]))?)
        }
        Some("drag") => {
            expect(4)?;
            Event::Drag(number(2)?, number(3)?)
        }
        Some("resize") => {
            expect(4)?;
            Event::Resize(size(2)?, size(3)?)
        }
        Some("capture") => {
            expect(3)?;
            Event::Capture(PathBuf::from(words[2]))
        }
        Some("quit") => {
            expect(2)?;
            Event::Quit
        }
        other => bail!("unknown event {other:?} (key, drag, resize, capture, quit)"),
    };
    Ok((frame, event))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_event_and_rejects_bad_lines() {
        let mut s = Script::parse(
            "# a comment\n5 key Digit2\n1 drag -3 4.5\n5 resize 0 0\n9 capture out/x.exr\n12 quit # done\n",
        )
        .unwrap();
        assert_eq!(s.take(0), vec![]);
        assert_eq!(s.take(1), vec![Event::Drag(-3.0, 4.5)]);
        assert_eq!(s.take(5), vec![Event::Key(KeyCode::Digit2), Event::Resize(0, 0)]);
        assert_eq!(s.take(100), vec![Event::Capture("out/x.exr".into()), Event::Quit]);
        for bad in ["x key KeyW", "3 key KeyZ", "3 drag 1", "3 resize -1 2", "3 jump", "3 quit now"] {
            let e = Script::parse(bad).unwrap_err();
            assert!(format!("{e:#}").contains("line 1"), "{bad}: {e:#}");
        }
    }
}
