-- gaitgram for Neovim 0.7 to 0.11 (Debian 12 ships 0.7.2): copy to
-- ~/.config/nvim/plugin/gaitgram.lua. Needs `gaitgram` on PATH (`pip install gaitgram`).
-- On Neovim 0.11+ you may prefer lsp/gaitgram.lua beside this file (vim.lsp.config/enable).

-- *.gg is a gaitgram grammar (an autocommand: vim.filetype.add needs 0.8 to work unaided).
vim.cmd([[
  augroup gaitgram_filetype
    autocmd!
    autocmd BufRead,BufNewFile *.gg setfiletype gaitgram
  augroup END
]])

local config = {
  name = "gaitgram",
  cmd = { "gaitgram", "lsp" },
  root_dir = vim.fn.getcwd(),
}

local client_id = nil

local function attach(bufnr)
  if vim.lsp.start ~= nil then -- 0.8+: starts the client once, reuses it for later buffers
    vim.lsp.start(config, { bufnr = bufnr })
    return
  end
  -- 0.7: one client, started by hand and attached to each gaitgram buffer
  if client_id == nil or vim.lsp.get_client_by_id(client_id) == nil then
    client_id = vim.lsp.start_client(config)
  end
  if client_id ~= nil then
    vim.lsp.buf_attach_client(bufnr, client_id)
  end
end

vim.api.nvim_create_autocmd("FileType", {
  pattern = "gaitgram",
  callback = function(args)
    attach(args.buf)
  end,
})
