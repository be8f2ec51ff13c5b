//! The SVG text plotters writes, made safe to rasterize: a stroke of zero
//! length (a piece of a curve whose points fall on one pixel: plotters
//! rounds to whole pixels) draws nothing with butt caps, but resvg cannot
//! stroke it and warns ("path stroking failed") on every run that draws
//! one. Such elements are dropped; nothing visible changes.

/// `svg` without its `<polyline>` elements whose points are all one point
/// and its `<line>` elements whose ends coincide.
pub(crate) fn without_empty_strokes(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let Some(end) = tail.find('>') else {
            out.push_str(tail);
            return out;
        };
        let element = &tail[..=end];
        if !is_empty_stroke(element) {
            out.push_str(element);
        }
        rest = &tail[end + 1..];
    }
    out.push_str(rest);
    out
}

/// Whether `element` (one tag, `<…>`) is a self-closed polyline or line of
/// zero length.
fn is_empty_stroke(element: &str) -> bool {
    if !element.ends_with("/>") {
        return false;
    }
    if element.starts_with("<polyline ") {
        let Some(points) = attribute(element, "points") else {
            return false;
        };
        let mut each = points.split_whitespace();
        let Some(first) = each.next() else {
            return true;
        };
        return each.all(|p| p == first);
    }
    if element.starts_with("<line ") {
        let ends = ["x1", "y1", "x2", "y2"].map(|name| attribute(element, name));
        if let [Some(x1), Some(y1), Some(x2), Some(y2)] = ends {
            return x1 == x2 && y1 == y2;
        }
    }
    false
}

/// The value of attribute `name` of `element`, quoted with `"`.
fn attribute<'a>(element: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let from = element.find(&key)? + key.len();
    let length = element[from..].find('"')?;
    Some(&element[from..from + length])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strokes_of_zero_length_are_dropped_and_the_rest_kept_verbatim() {
        let svg = concat!(
            "<svg width=\"10\" height=\"10\">\n",
            "<polyline fill=\"none\" stroke=\"#1F77B4\" points=\"411,337 411,337 \"/>\n",
            "<polyline fill=\"none\" stroke=\"#1F77B4\" points=\"411,337 411,337 411,338 \"/>\n",
            "<line stroke=\"#000000\" x1=\"90\" y1=\"307\" x2=\"90\" y2=\"307\"/>\n",
            "<line stroke=\"#000000\" x1=\"90\" y1=\"307\" x2=\"1089\" y2=\"307\"/>\n",
            "<text x=\"1\" y=\"2\">a &lt; b</text>\n",
            "</svg>\n"
        );
        let expected = concat!(
            "<svg width=\"10\" height=\"10\">\n",
            "\n",
            "<polyline fill=\"none\" stroke=\"#1F77B4\" points=\"411,337 411,337 411,338 \"/>\n",
            "\n",
            "<line stroke=\"#000000\" x1=\"90\" y1=\"307\" x2=\"1089\" y2=\"307\"/>\n",
            "<text x=\"1\" y=\"2\">a &lt; b</text>\n",
            "</svg>\n"
        );
        assert_eq!(without_empty_strokes(svg), expected);
        // Idempotent, and a text without such strokes is unchanged.
        assert_eq!(without_empty_strokes(expected), expected);
    }

    #[test]
    fn a_truncated_text_is_kept_as_it_is() {
        let svg = "<svg><polyline points=\"1,1 1,1\"/><line x1=\"1";
        assert_eq!(without_empty_strokes(svg), "<svg><line x1=\"1");
    }
}
