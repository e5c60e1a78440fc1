// SPDX-License-Identifier: MIT
// The report page's style sheet (injected, so that the page is one script and its data).
export const STYLE = `
body { margin: 0; background: #0f1115; color: #dde3ea; font: 14px/1.4 system-ui, sans-serif; }
header { padding: 12px 20px 4px; }
h1 { font-size: 18px; margin: 0 0 4px; font-weight: 600; }
#summary { margin: 0; color: #aab2bd; }
#live-status { color: #2ec4b6; font-size: 12px; }
main { display: flex; flex-wrap: wrap; gap: 16px; padding: 12px 20px 20px; }
#view { flex: 1 1 100%; min-width: 420px; }
#layers { display: flex; gap: 14px; align-items: center; margin-bottom: 6px; color: #aab2bd; }
#canvas-box { height: 62vh; min-height: 420px; border: 1px solid #2a2f37; border-radius: 4px; overflow: hidden; }
#plots { flex: 1 1 100%; display: grid; grid-template-columns: repeat(auto-fill, minmax(540px, 1fr)); gap: 10px; }
figure { margin: 0; background: #15181d; border: 1px solid #2a2f37; border-radius: 4px; padding: 6px 8px; }
figcaption { color: #aab2bd; font-size: 12px; margin-bottom: 2px; }
figure canvas { width: 100%; height: 190px; display: block; }
#lost { color: #ff8a8a; margin: 0; grid-column: 1 / -1; }
select { background: #15181d; color: #dde3ea; border: 1px solid #2a2f37; }
`;
