// The page's router: #/ jobs, #/submit, #/jobs/{id}, #/compare/{id,id,…},
// #/studies, #/studies/{id}.
// Each page is a module with show(main, args) returning a stop() function
// (polling timers, WebGL contexts) called when the page is left.
import { replace, el } from './dom.js';
import * as jobs from './jobs.js';
import * as submit from './submit.js';
import * as job from './job.js';
import * as compare from './compare.js';
import * as studies from './studies.js';

const main = document.getElementById('main');
let stop = null;

function route() {
  if (stop) { try { stop(); } catch (e) { console.warn(e); } stop = null; }
  const hash = decodeURIComponent(location.hash.replace(/^#/, '')) || '/';
  const parts = hash.split('/').filter(Boolean);
  replace(main);
  window.scrollTo(0, 0);
  if (parts.length === 0) stop = jobs.show(main);
  else if (parts[0] === 'submit') stop = submit.show(main);
  else if (parts[0] === 'jobs' && parts.length === 2) stop = job.show(main, parts[1]);
  else if (parts[0] === 'studies' && parts.length === 1) stop = studies.showList(main);
  else if (parts[0] === 'studies' && parts.length === 2) stop = studies.show(main, parts[1]);
  else if (parts[0] === 'compare') stop = compare.show(main, (parts[1] || '').split(',').filter(Boolean));
  else main.append(el('p', {}, 'No such page. ', el('a', { href: '#/' }, 'Jobs')));
}

window.addEventListener('hashchange', route);
route();
