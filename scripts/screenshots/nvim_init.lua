-- Neovim's built-in LSP client on `snell lsp`, driven for the documentation's
-- editor screenshots (scripts/editor_screenshots.sh). SHOT chooses the picture:
--   diagnostics  the error under the cursor in a float, with its note
--   completion   the property completions inside a sphere block
vim.o.termguicolors = false
vim.o.number = true
vim.o.signcolumn = "yes"
vim.o.completeopt = "menuone,noinsert"
vim.o.pumheight = 12
vim.cmd("syntax off")
vim.cmd("highlight Pmenu ctermbg=238 ctermfg=255")
vim.cmd("highlight PmenuSel ctermbg=24 ctermfg=255")
vim.cmd("highlight NormalFloat ctermbg=236 ctermfg=255")
vim.diagnostic.config({ virtual_text = true, signs = true, underline = true,
                        float = { border = "single", source = false } })
local snell = os.getenv("SNELL")
local shot = os.getenv("SHOT")
vim.api.nvim_create_autocmd("BufRead", { pattern = "*.scn", callback = function(args)
  local id = vim.lsp.start_client({ name = "snell", cmd = { snell, "lsp" },
                                    root_dir = vim.fn.getcwd() })
  vim.lsp.buf_attach_client(args.buf, id)
  vim.bo[args.buf].omnifunc = "v:lua.vim.lsp.omnifunc"
end })
-- After the server has answered (diagnostics are pushed on open).
vim.defer_fn(function()
  if shot == "diagnostics" then
    vim.api.nvim_win_set_cursor(0, { 5, 28 })
    -- Later than the cursor move, whose CursorMoved would close the float at once.
    vim.defer_fn(function() vim.diagnostic.open_float(nil, { scope = "line" }) end, 300)
  elseif shot == "completion" then
    vim.api.nvim_win_set_cursor(0, { 6, 42 })
    vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes("i <C-x><C-o>", true, false, true),
                          "n", false)
  end
end, 2000)
