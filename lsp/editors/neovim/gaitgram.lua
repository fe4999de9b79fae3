-- gaitgram for Neovim (0.7+): put this in ~/.config/nvim/after/plugin/gaitgram.lua
vim.filetype.add({ extension = { gg = "gaitgram" } })
vim.api.nvim_create_autocmd("FileType", {
  pattern = "gaitgram",
  callback = function(args)
    vim.lsp.start({
      name = "gaitgram",
      cmd = { "gaitgram", "lsp" },
      root_dir = vim.fs.dirname(vim.api.nvim_buf_get_name(args.buf)),
    })
  end,
})
