//! Connected components of a raster's features, numbered in scan order, so
//! that each pixel can take the component of its nearest feature: the
//! Voronoi diagram of the obstacles in a raster.

/// No component.
pub const NO_COMPONENT: u32 = u32::MAX;

/// The connected components of `features` (row-major, `width` wide) under
/// 8-connectivity (pixels that share an edge or a corner): each feature
/// pixel's component, numbered 0, 1, ... in the order of their first pixel
/// (row by row), [`NO_COMPONENT`] elsewhere; and their number.
pub fn components(features: &[bool], width: usize) -> crate::Result<(Vec<u32>, u32)> {
    let mut parent: Vec<u32> = Vec::new();
    let mut labels = crate::memory::filled(features.len(), NO_COMPONENT, "component labels")?;
    fn root(parent: &mut [u32], mut a: u32) -> u32 {
        while parent[a as usize] != a {
            parent[a as usize] = parent[parent[a as usize] as usize];
            a = parent[a as usize];
        }
        a
    }
    for p in (0..features.len()).filter(|&p| features[p]) {
        let (x, y) = (p % width, p / width);
        // The neighbours already labelled: left, and the three above.
        let mut before = [None; 4];
        if x > 0 {
            before[0] = Some(p - 1);
        }
        if y > 0 {
            let above = p - width;
            before[1] = (x > 0).then(|| above - 1);
            before[2] = Some(above);
            before[3] = (x + 1 < width).then_some(above + 1);
        }
        let mut label = NO_COMPONENT;
        for q in before.into_iter().flatten().filter(|&q| features[q]) {
            let r = root(&mut parent, labels[q]);
            if label == NO_COMPONENT {
                label = r;
            } else if r != label {
                let (keep, merge) = (label.min(r), label.max(r));
                parent[merge as usize] = keep;
                label = keep;
            }
        }
        if label == NO_COMPONENT {
            label = parent.len() as u32;
            parent.push(label);
        }
        labels[p] = label;
    }
    // Provisional labels were made in scan order and merged into the smaller,
    // so numbering the roots in order numbers components by first pixel.
    let mut number = crate::memory::filled(parent.len(), NO_COMPONENT, "component numbers")?;
    let mut count = 0;
    for a in 0..parent.len() as u32 {
        let r = root(&mut parent, a);
        if number[r as usize] == NO_COMPONENT {
            number[r as usize] = count;
            count += 1;
        }
    }
    for l in labels.iter_mut().filter(|l| **l != NO_COMPONENT) {
        *l = number[root(&mut parent, *l) as usize];
    }
    Ok((labels, count))
}
