-- gaitgram for Neovim 0.11+, the vim.lsp.config way. Put this file on the runtime path as
-- lsp/gaitgram.lua (for example ~/.config/nvim/lsp/gaitgram.lua), then in init.lua:
--   vim.filetype.add({ extension = { gg = "gaitgram" } })
--   vim.lsp.enable("gaitgram")
return {
  cmd = { "gaitgram", "lsp" },
  filetypes = { "gaitgram" },
  root_markers = { ".git", "pyproject.toml" },
}
