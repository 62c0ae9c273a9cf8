// Starts Debian's Chromium headless with WebGL2 on SwiftShader (software), for check.mjs and bench.mjs.
// Only the page's own console and errors are collected: Chromium's stderr is GPU noise, never read.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

export const CHROMIUM = process.env.KEZURI_CHROMIUM || '/usr/bin/chromium';
export const FLAGS = [
  '--no-sandbox',
  '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--no-first-run', '--disable-quic', '--disable-extensions', '--mute-audio',
];

// A fresh browser (own profile folder, removed by close()) and one page with its problems recorded.
export async function open({ width = 1280, height = 800 } = {}) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'kezuri-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM, headless: true, args: FLAGS, viewport: { width, height }, deviceScaleFactor: 1,
  });
  const page = context.pages()[0] || (await context.newPage());
  const problems = [];
  const dialogs = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push('console: ' + m.text()); });
  page.on('pageerror', (e) => problems.push('page error: ' + e.message));
  page.on('dialog', (d) => { dialogs.push(d.type() + ': ' + d.message()); d.dismiss().catch(() => {}); });
  const close = async () => {
    await context.close().catch(() => {});
    fs.rmSync(profile, { recursive: true, force: true });
  };
  return { page, problems, dialogs, close };
}

// Loads a page file and waits for its first frame (data-ready="1") or its error (data-error).
export async function load(page, file, timeoutMs = 120000) {
  const t0 = Date.now();
  await page.goto('file://' + path.resolve(file), { waitUntil: 'commit', timeout: timeoutMs });
  await page.waitForFunction(() => document.documentElement.dataset.ready === '1' || document.documentElement.dataset.error !== undefined,
    null, { timeout: timeoutMs, polling: 20 });
  const wallMs = Date.now() - t0;
  const r = await page.evaluate(() => ({
    ready: document.documentElement.dataset.ready === '1',
    error: document.documentElement.dataset.error || null,
    readyMs: window.kezuriView ? window.kezuriView.readyMs : null,
  }));
  return { ...r, wallMs };
}
