//! Merging runs of smooth segments of traced outlines into disk Wang–Ball curves.
