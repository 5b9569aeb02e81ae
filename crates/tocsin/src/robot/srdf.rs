//! The part of SRDF (MoveIt's semantic robot description) the checks use: the
//! `<disable_collisions link1=".." link2=".." reason=".."/>` pairs. Groups, end effectors and
//! virtual joints do not change which pairs may touch, and are not read.

use super::RobotError;
use std::path::PathBuf;

/// The link name pairs the SRDF disables.
pub(super) fn disabled_pairs(xml: &str) -> Result<Vec<(String, String)>, RobotError> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| RobotError::Parse {
        path: PathBuf::from("<srdf>"),
        message: e.to_string(),
    })?;
    let mut pairs = Vec::new();
    for node in doc
        .descendants()
        .filter(|n| n.has_tag_name("disable_collisions"))
    {
        let (Some(a), Some(b)) = (node.attribute("link1"), node.attribute("link2")) else {
            return Err(RobotError::Parse {
                path: PathBuf::from("<srdf>"),
                message: format!(
                    "line {}: <disable_collisions> needs link1 and link2",
                    doc.text_pos_at(node.range().start).row
                ),
            });
        };
        pairs.push((a.to_string(), b.to_string()));
    }
    Ok(pairs)
}
