//! Helpers for the XML formats read with roxmltree (COLLADA meshes, URDF): parsing with a
//! document type declaration allowed (exporters write one), and a text with elements cut out.

use std::ops::Range;

/// The document, a `<!DOCTYPE>` allowed.
pub(crate) fn parse(text: &str) -> Result<roxmltree::Document<'_>, roxmltree::Error> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    roxmltree::Document::parse_with_options(text, options)
}

/// `text` without the byte ranges `cut` (elements' [`roxmltree::Node::range`]s); a range
/// inside one already cut goes with it.
pub(crate) fn without(text: &str, mut cut: Vec<Range<usize>>) -> String {
    cut.sort_by_key(|r| r.start);
    let mut out = String::with_capacity(text.len());
    let mut from = 0;
    for r in cut {
        if r.start >= from {
            out.push_str(&text[from..r.start]);
            from = r.end;
        }
    }
    out.push_str(&text[from..]);
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    #[test]
    fn nested_and_unordered_cuts_keep_the_rest() {
        let text = "<a><b><c/></b><d/><e/></a>";
        let doc = super::parse(text).unwrap();
        let range = |name: &str| {
            doc.descendants()
                .find(|n| n.has_tag_name(name))
                .unwrap()
                .range()
        };
        let cut = vec![range("e"), range("c"), range("b")];
        assert_eq!(super::without(text, cut), "<a><d/></a>");
    }
}
