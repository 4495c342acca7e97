// MathJax 3 for the \( \) and \[ \] spans pymdownx.arithmatex writes (generic mode); \tag{N}
// numbers an equation as in the paper. The script itself is served from the site (sitegen/hooks.py).
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"]],
    displayMath: [["\\[", "\\]"]],
    processEscapes: true,
    processEnvironments: true,
    tags: "none",
  },
  options: {
    ignoreHtmlClass: ".*|",
    processHtmlClass: "arithmatex",
  },
  svg: { fontCache: "global" },
};
