;;; gaitgram-eglot.el --- gaitgram grammars in Emacs with eglot
(define-derived-mode gaitgram-mode prog-mode "gaitgram"
  "Major mode for gaitgram .gg grammars."
  (setq-local comment-start "# "))
(add-to-list 'auto-mode-alist '("\\.gg\\'" . gaitgram-mode))
(with-eval-after-load 'eglot
  (add-to-list 'eglot-server-programs '(gaitgram-mode . ("gaitgram" "lsp"))))
(add-hook 'gaitgram-mode-hook #'eglot-ensure)
;;; gaitgram-eglot.el ends here
