"""Reports of studies and run directories: the records read back, the statistics, the sections as data,
and their formats (text, HTML, figures, GIFs); built on the study floor's manifest, never running a study."""
