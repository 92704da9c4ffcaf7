"""Real-browser test harness: a JupyterLab server and headless Debian Chromium driven by Playwright."""
