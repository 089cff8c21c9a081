# SPDX-License-Identifier: MIT
# @brief Tests of the virtual head (unit) and the desktop window (label gl: a window on an Xvfb
#        the test starts itself, X input injected with XTest; skipped, saying why, without Xvfb).
telesphere_add_test(test_virtual_head SOURCES test_virtual_head.cpp
  LIBS telesphere::xr_virtual_head)

telesphere_add_test(xr_desktop_window_test SOURCES desktop_window_test.cpp
  LIBS telesphere::xr_desktop X11 Xtst LABELS gl)
set_tests_properties(xr_desktop_window_test PROPERTIES
  SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
