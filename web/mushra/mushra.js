// The MUSHRA test page of room_reverb (`room_reverb mushra make` writes it next to the
// test; `room_reverb mushra serve` serves it). Everything it needs comes as scripts:
// test.js sets window.MUSHRA_TEST (test.json), and audio/<room>/<content>/<condition>.js
// adds one stimulus (a 16-bit WAV in base64) to window.MUSHRA_AUDIO. Scripts, because a
// page opened from the file system may load scripts but may not fetch() its neighbours.
//
// Playback: every stimulus of a page is decoded once into an AudioBuffer; "play" starts
// all of them at the same context time and offset, each through its own gain, and only the
// selected one is heard. Switching is then a change of gains, so it is instant and the new
// stimulus continues at exactly the same sample. The gains move linearly over 5 ms (a
// crossfade: the stimuli are versions of one dry recording, strongly correlated, so the
// linear fade keeps the level even), which removes the click a hard switch would make.
"use strict";

(function () {
  const kCrossfadeS = 0.005;  // see above
  const kStartDelayS = 0.03;  // schedule starts a little ahead so every source makes it
  const kMinLoopS = 0.2;      // the shortest loop region the inputs allow

  const test = window.MUSHRA_TEST;
  const $ = (id) => document.getElementById(id);

  function fail(message) {
    const box = $("fatal");
    box.textContent = message;
    box.hidden = false;
  }

  // ---- Randomisation per listener ---------------------------------------------------------
  // A 32-bit FNV-1a hash of the listener's name and the start time seeds a xorshift32
  // generator; the seed is written into the results (session_seed), so the order a
  // listener met can be recreated.
  function hash32(text) {
    let h = 0x811c9dc5;
    for (let i = 0; i < text.length; ++i) {
      h ^= text.charCodeAt(i);
      h = Math.imul(h, 0x01000193) >>> 0;
    }
    return h || 1;  // xorshift must not start at 0
  }

  function makeRandom(seed) {
    let x = seed >>> 0 || 1;
    return function () {
      x ^= x << 13; x >>>= 0;
      x ^= x >>> 17;
      x ^= x << 5; x >>>= 0;
      return x / 4294967296;
    };
  }

  function shuffled(count, random) {
    const order = Array.from({length: count}, (_, i) => i);
    for (let i = count - 1; i > 0; --i) {
      const j = Math.floor(random() * (i + 1));
      [order[i], order[j]] = [order[j], order[i]];
    }
    return order;
  }

  // ---- Results ---------------------------------------------------------------------------
  // The nine columns `room_reverb mushra analyze` reads, then two it ignores that record
  // this listener's randomisation.
  const kColumns = ["listener", "page", "room", "content", "attribute", "condition", "letter", "score",
                    "duration_s", "page_position", "session_seed"];

  function csvField(value) {
    const text = String(value);
    return /[",\r\n]/.test(text) ? '"' + text.replace(/"/g, '""') + '"' : text;
  }

  function resultsCsv(rows) {
    const lines = [kColumns.join(",")];
    for (const row of rows) lines.push(kColumns.map((c) => csvField(row[c])).join(","));
    return lines.join("\n") + "\n";
  }

  function safeFileName(text) {
    return text.replace(/[^A-Za-z0-9_.-]+/g, "_").slice(0, 60) || "listener";
  }

  function timestamp() {
    const d = new Date();
    const two = (n) => String(n).padStart(2, "0");
    return d.getFullYear() + two(d.getMonth() + 1) + two(d.getDate()) + "-" + two(d.getHours()) +
           two(d.getMinutes()) + two(d.getSeconds());
  }

  // ---- Audio -----------------------------------------------------------------------------
  const audio = {
    context: null,
    decoded: new Map(),  // stimulus file -> Promise<AudioBuffer>
    scripts: new Map(),  // script path -> Promise
  };

  function loadScript(path) {
    if (!audio.scripts.has(path)) {
      audio.scripts.set(path, new Promise((resolve, reject) => {
        const element = document.createElement("script");
        element.src = path;
        element.onload = resolve;
        element.onerror = () => reject(new Error(path + " could not be loaded"));
        document.head.appendChild(element);
      }));
    }
    return audio.scripts.get(path);
  }

  function base64Bytes(text) {
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
    return bytes.buffer;
  }

  function decodedStimulus(stimulus) {
    if (!audio.decoded.has(stimulus.file)) {
      const script = stimulus.audio_script || stimulus.file.replace(/^stimuli\//, "audio/").replace(/\.wav$/, ".js");
      audio.decoded.set(stimulus.file, loadScript(script).then(() => {
        const store = window.MUSHRA_AUDIO || {};
        const text = store[stimulus.file];
        if (typeof text !== "string") throw new Error(script + " holds no audio for " + stimulus.file);
        delete store[stimulus.file];  // the decoded buffer is all that is needed from now on
        return audio.context.decodeAudioData(base64Bytes(text));
      }));
    }
    return audio.decoded.get(stimulus.file);
  }

  // ---- One page --------------------------------------------------------------------------
  const state = {
    listener: "",
    seed: 0,
    random: null,
    pageOrder: [],
    position: 0,       // index into pageOrder
    rows: [],
    page: null,        // the current page's view (below)
    finished: false,
  };

  // The current page: its stimuli in display order (letter A first), their buffers, and
  // the transport.
  function newPageView(page) {
    const order = shuffled(page.stimuli.length, state.random);
    return {
      page,
      stimuli: order.map((k, i) => ({
        source: page.stimuli[k],
        letter: String.fromCharCode(65 + i),
        played: false,
        rated: false,
        buffer: null,
      })),
      references: page.stimuli.map((s, k) => ({stimulus: s, index: order.indexOf(k)}))
                              .filter((r) => r.stimulus.is_shown_reference),
      ready: false,
      shownAt: performance.now(),
      selected: {kind: "stimulus", index: 0},
      playing: false,
      nodes: [],           // per display stimulus: {source, gain} while playing
      master: null,
      startTime: 0,        // context time at which `startOffset` plays
      startOffset: 0,
      pausedAt: 0,         // position while stopped
      duration: 0,
      loopStart: 0,
      loopEnd: 0,
    };
  }

  function formatS(seconds) {
    return seconds.toFixed(2) + " s";
  }

  function currentPosition(view) {
    if (!view.playing) return view.pausedAt;
    const elapsed = Math.max(0, audio.context.currentTime - view.startTime);
    let position = view.startOffset + elapsed;
    if (position >= view.loopEnd) {
      const length = view.loopEnd - view.loopStart;
      position = view.loopStart + ((position - view.loopStart) % length);
    }
    return position;
  }

  function startPlayback(view) {
    const context = audio.context;
    if (context.state === "suspended") context.resume();
    let offset = view.pausedAt;
    if (offset < view.loopStart || offset >= view.loopEnd - 0.01) offset = view.loopStart;
    const when = context.currentTime + kStartDelayS;
    view.master = context.createGain();
    view.master.gain.setValueAtTime(0, when);
    view.master.gain.linearRampToValueAtTime(1, when + kCrossfadeS);
    view.master.connect(context.destination);
    const selected = view.selected.index;
    view.nodes = view.stimuli.map((s, i) => {
      const source = context.createBufferSource();
      source.buffer = s.buffer;
      source.loop = true;
      source.loopStart = view.loopStart;
      source.loopEnd = view.loopEnd;
      const gain = context.createGain();
      gain.gain.value = i === selected ? 1 : 0;
      source.connect(gain).connect(view.master);
      source.start(when, offset);
      return {source, gain};
    });
    view.startTime = when;
    view.startOffset = offset;
    view.playing = true;
    notePlayed(view);
    updateTransport(view);
  }

  function stopPlayback(view, keepPosition) {
    if (!view.playing) return;
    const position = currentPosition(view);
    const context = audio.context;
    const now = context.currentTime;
    view.master.gain.cancelScheduledValues(now);
    view.master.gain.setValueAtTime(view.master.gain.value, now);
    view.master.gain.linearRampToValueAtTime(0, now + kCrossfadeS);
    for (const node of view.nodes) node.source.stop(now + kCrossfadeS + 0.005);
    const master = view.master;
    setTimeout(() => master.disconnect(), 100);
    view.nodes = [];
    view.master = null;
    view.playing = false;
    view.pausedAt = keepPosition ? position : view.loopStart;
    updateTransport(view);
  }

  // A stimulus counts as played once it was heard: selected while the transport runs.
  function notePlayed(view) {
    if (view.playing && view.selected.kind === "stimulus") {
      view.stimuli[view.selected.index].played = true;
      updateStimulusViews(view);
    }
  }

  // The shown references play the same buffer as their hidden letter, but hearing them
  // does not count as having played that letter.
  function selectReference(view, k) {
    select(view, "reference", view.references[k].index, k);
  }

  function select(view, kind, index, reference) {
    view.selected = {kind, index, reference};
    if (view.playing) {
      const now = audio.context.currentTime;
      view.nodes.forEach((node, i) => {
        const gain = node.gain.gain;
        gain.cancelScheduledValues(now);
        gain.setValueAtTime(gain.value, now);
        gain.linearRampToValueAtTime(i === index ? 1 : 0, now + kCrossfadeS);
      });
      notePlayed(view);
    } else {
      startPlayback(view);
    }
    updateSelection(view);
  }

  function togglePlayback(view) {
    if (view.playing) stopPlayback(view, false);
    else startPlayback(view);
  }

  // A new loop region (or a new position) while playing restarts every source there: the
  // sources' loop points could move live, but a position outside the new region could not.
  function restartAt(view, position) {
    const wasPlaying = view.playing;
    if (wasPlaying) stopPlayback(view, true);
    view.pausedAt = Math.min(Math.max(position, view.loopStart), view.loopEnd);
    if (wasPlaying) startPlayback(view);
    updateTransport(view);
  }

  function setLoop(view, start, end) {
    view.loopStart = Math.max(0, Math.min(start, view.duration - kMinLoopS));
    view.loopEnd = Math.min(view.duration, Math.max(end, view.loopStart + kMinLoopS));
    $("loop-start").value = view.loopStart;
    $("loop-end").value = view.loopEnd;
    $("loop-start-value").textContent = formatS(view.loopStart);
    $("loop-end-value").textContent = formatS(view.loopEnd);
    restartAt(view, view.playing ? currentPosition(view) : view.loopStart);
  }

  // ---- Drawing ---------------------------------------------------------------------------
  function updateTransport(view) {
    $("play").textContent = view.playing ? "Stop" : "Play";
    $("play").classList.toggle("selected", view.playing);
  }

  function updateSelection(view) {
    view.stimuli.forEach((s, i) => {
      s.button.classList.toggle("selected", view.selected.kind === "stimulus" && view.selected.index === i);
    });
    view.references.forEach((r, k) => {
      r.button.classList.toggle("selected", view.selected.kind === "reference" && view.selected.reference === k);
    });
  }

  function updateStimulusViews(view) {
    let missing = 0;
    for (const s of view.stimuli) {
      s.element.classList.toggle("done", s.played && s.rated);
      s.value.textContent = s.rated ? s.slider.value : "–";
      if (!(s.played && s.rated)) ++missing;
    }
    const last = state.position === state.pageOrder.length - 1;
    $("next").textContent = last ? "Finish" : "Next";
    $("next").disabled = !view.ready || missing > 0;
    $("next-hint").textContent = missing > 0
        ? "Play and rate every excerpt to continue (" + missing + " left)." : "";
  }

  function animate() {
    const view = state.page;
    if (view && view.ready && !state.finished) {
      const position = currentPosition(view);
      $("time").textContent = formatS(position);
      const width = $("timeline").clientWidth;
      $("playhead").style.left = (width * position / view.duration) + "px";
      $("loop-region").style.left = (width * view.loopStart / view.duration) + "px";
      $("loop-region").style.width = (width * (view.loopEnd - view.loopStart) / view.duration) + "px";
    }
    requestAnimationFrame(animate);
  }

  function buildPage(view) {
    const page = view.page;
    $("question").textContent = page.question;
    const panorama = $("panorama");
    if (page.panorama) {
      panorama.src = page.panorama;
      panorama.hidden = false;
    } else {
      panorama.removeAttribute("src");
      panorama.hidden = true;
    }
    $("progress").max = state.pageOrder.length;
    $("progress").value = state.position;
    $("progress-text").textContent = "Page " + (state.position + 1) + " of " + state.pageOrder.length;

    const references = $("references");
    references.textContent = "";
    view.references.forEach((r, k) => {
      const button = document.createElement("button");
      button.type = "button";
      button.className = "reference";
      const name = r.stimulus.condition === "reference" ? "" : ": " + r.stimulus.condition.replace(/_/g, " ");
      button.textContent = "Reference" + (view.references.length > 1 ? name : "");
      button.disabled = true;
      button.addEventListener("click", () => selectReference(view, k));
      r.button = button;
      references.appendChild(button);
    });

    const container = $("stimuli");
    container.textContent = "";
    const labels = document.createElement("div");
    labels.className = "scale-labels";
    const scale = test.scale;
    const steps = scale.max === 100 ? ["100 Excellent", "80 Good", "60 Fair", "40 Poor", "20 Bad", "0"]
                                    : Array.from({length: scale.max - scale.min + 1}, (_, i) => String(scale.max - i));
    for (const text of steps) {
      const label = document.createElement("span");
      label.textContent = text;
      labels.appendChild(label);
    }
    container.appendChild(labels);
    view.stimuli.forEach((s, i) => {
      const element = document.createElement("div");
      element.className = "stimulus";
      const button = document.createElement("button");
      button.type = "button";
      button.className = "play-stimulus";
      button.id = "stimulus-" + i;
      button.textContent = s.letter;
      button.title = "Play " + s.letter + " (key " + (i + 1) + ")";
      button.disabled = true;
      button.addEventListener("click", () => select(view, "stimulus", i));
      const slider = document.createElement("input");
      slider.type = "range";
      slider.className = "score";
      slider.id = "score-" + i;
      slider.min = scale.min;
      slider.max = scale.max;
      slider.step = scale.step;
      slider.value = scale.min;
      slider.disabled = true;
      slider.setAttribute("aria-label", "Rating of " + s.letter);
      slider.addEventListener("input", () => {
        s.rated = true;
        updateStimulusViews(view);
      });
      const value = document.createElement("output");
      value.className = "score-value";
      element.append(button, slider, value);
      container.appendChild(element);
      Object.assign(s, {element, button, slider, value});
    });
    $("play").disabled = true;
    updateStimulusViews(view);
    updateSelection(view);
    updateTransport(view);
  }

  function enableControls(view, enabled) {
    $("play").disabled = !enabled;
    for (const s of view.stimuli) s.button.disabled = s.slider.disabled = !enabled;
    for (const r of view.references) r.button.disabled = !enabled;
    for (const id of ["loop-start", "loop-end", "loop-reset"]) $(id).disabled = !enabled;
  }

  // ---- The test's flow -------------------------------------------------------------------
  function showPage() {
    const page = test.pages[state.pageOrder[state.position]];
    const view = newPageView(page);
    state.page = view;
    buildPage(view);
    enableControls(view, false);
    $("page-status").textContent = "Loading the excerpts…";
    Promise.all(view.stimuli.map((s) => decodedStimulus(s.source))).then((buffers) => {
      if (state.page !== view) return;
      buffers.forEach((b, i) => { view.stimuli[i].buffer = b; });
      view.duration = Math.min(...buffers.map((b) => b.duration));
      for (const id of ["loop-start", "loop-end"]) $(id).max = view.duration;
      view.ready = true;
      view.readyAfter = (performance.now() - view.shownAt) / 1000;
      setLoop(view, 0, view.duration);
      enableControls(view, true);
      $("page-status").textContent = "";
      document.body.dataset.page = page.id;  // for a scripted listener: this page is ready
      updateStimulusViews(view);
      preloadNext();
    }).catch((error) => fail("Cannot load the audio of page " + page.id + ": " + error.message));
  }

  // Decoding the next page's stimuli while this one is rated hides the loading time.
  function preloadNext() {
    const next = state.position + 1;
    if (next >= state.pageOrder.length) return;
    for (const s of test.pages[state.pageOrder[next]].stimuli) decodedStimulus(s).catch(() => {});
  }

  function finishPage() {
    const view = state.page;
    if (!view || !view.ready || $("next").disabled) return;
    stopPlayback(view, false);
    const seconds = (performance.now() - view.shownAt) / 1000;
    const page = view.page;
    for (const s of view.stimuli) {
      state.rows.push({
        listener: state.listener, page: page.id, room: page.room, content: page.content,
        attribute: page.attribute, condition: s.source.condition, letter: s.letter, score: s.slider.value,
        duration_s: seconds.toFixed(3), page_position: state.position + 1, session_seed: state.seed,
      });
    }
    delete document.body.dataset.page;
    if (state.position + 1 < state.pageOrder.length) {
      ++state.position;
      showPage();
    } else {
      finishTest();
    }
  }

  function download(csv, name) {
    const url = URL.createObjectURL(new Blob([csv], {type: "text/csv"}));
    const link = document.createElement("a");
    link.href = url;
    link.download = name;
    document.body.appendChild(link);
    link.click();
    link.remove();
    setTimeout(() => URL.revokeObjectURL(url), 60000);
  }

  function finishTest() {
    state.finished = true;
    state.page = null;
    window.removeEventListener("beforeunload", warnBeforeLeaving);
    const csv = resultsCsv(state.rows);
    const name = "mushra_" + safeFileName(state.listener) + "_" + timestamp() + ".csv";
    $("test-view").hidden = true;
    $("end-view").hidden = false;
    $("results-csv").value = csv;
    $("download-name").textContent = name;
    $("download").addEventListener("click", () => download(csv, name));
    download(csv, name);
    if (location.protocol === "http:" || location.protocol === "https:") {
      $("post-status").textContent = "Sending the results to the test server…";
      fetch("results", {method: "POST", headers: {"Content-Type": "text/csv"}, body: csv})
        .then((response) => response.json().then((answer) => ({ok: response.ok, answer})))
        .then(({ok, answer}) => {
          $("post-status").textContent = ok ? "Saved on the test server as " + answer.saved + "."
                                            : "The test server refused the results: " + answer.error;
          document.body.dataset.posted = ok ? "saved" : "refused";
        })
        .catch((error) => {
          $("post-status").textContent = "Could not reach the test server (" + error.message +
                                         "); please send the downloaded file.";
          document.body.dataset.posted = "failed";
        });
    }
    document.body.dataset.finished = "true";
  }

  function warnBeforeLeaving(event) {
    event.preventDefault();
    event.returnValue = "";
  }

  function start() {
    const name = $("listener-name").value.trim();
    if (!name) return;
    // Created on the click: browsers let a context make sound only after a user gesture.
    // At the test's rate when the browser allows it, so that decoding does not resample.
    try {
      audio.context = new AudioContext({sampleRate: test.sample_rate_hz});
    } catch (error) {
      audio.context = new AudioContext();
    }
    state.listener = name;
    state.seed = hash32(name + "|" + Date.now());
    state.random = makeRandom(state.seed);
    state.pageOrder = shuffled(test.pages.length, state.random);
    window.addEventListener("beforeunload", warnBeforeLeaving);
    $("start-view").hidden = true;
    $("test-view").hidden = false;
    showPage();
    requestAnimationFrame(animate);
  }

  // ---- Keyboard --------------------------------------------------------------------------
  function onKey(event) {
    const view = state.page;
    if (!view || !view.ready || event.ctrlKey || event.altKey || event.metaKey) return;
    if (event.target instanceof HTMLInputElement && event.target.type === "text") return;
    const key = event.key;
    let handled = true;
    if (key >= "1" && key <= "9") {
      const index = Number(key) - 1;
      if (index < view.stimuli.length) select(view, "stimulus", index);
    } else if (key === " ") {
      togglePlayback(view);
    } else if (key === "r" || key === "R") {
      if (view.references.length) {
        const current = view.selected.kind === "reference" ? view.selected.reference : -1;
        selectReference(view, (current + 1) % view.references.length);
      }
    } else if (key === "n" || key === "N") {
      finishPage();
    } else {
      handled = false;
    }
    // A focused button would also act on Space (on key-up); the shortcut wins.
    if (handled) event.preventDefault();
  }

  // ---- Wiring ----------------------------------------------------------------------------
  function init() {
    if (!test || !Array.isArray(test.pages) || !test.pages.length) {
      fail("test.js is missing or holds no pages: open the index.html that `room_reverb mushra make` wrote, " +
           "in the folder that holds test.js and audio/.");
      return;
    }
    if (!window.AudioContext) {
      fail("This browser has no Web Audio API; please use a current Chromium, Chrome, Firefox or Safari.");
      return;
    }
    $("start-page-count").textContent = String(test.pages.length);
    $("start-scale").textContent = test.scale.min + " to " + test.scale.max;
    const name = $("listener-name");
    name.addEventListener("input", () => { $("start").disabled = !name.value.trim(); });
    name.addEventListener("keydown", (event) => { if (event.key === "Enter") start(); });
    $("start").addEventListener("click", start);
    $("play").addEventListener("click", () => state.page && togglePlayback(state.page));
    $("next").addEventListener("click", finishPage);
    $("loop-start").addEventListener("input", (event) => {
      const view = state.page;
      if (view) setLoop(view, Number(event.target.value), view.loopEnd);
    });
    $("loop-end").addEventListener("input", (event) => {
      const view = state.page;
      if (view) setLoop(view, view.loopStart, Number(event.target.value));
    });
    $("loop-reset").addEventListener("click", () => state.page && setLoop(state.page, 0, state.page.duration));
    $("timeline").addEventListener("click", (event) => {
      const view = state.page;
      if (!view || !view.ready) return;
      const box = $("timeline").getBoundingClientRect();
      restartAt(view, view.duration * (event.clientX - box.left) / box.width);
    });
    document.addEventListener("keydown", onKey);
    document.addEventListener("keyup", (event) => {
      if (event.key === " " && state.page) event.preventDefault();
    });
    document.body.dataset.loaded = "true";
  }

  // For scripted listeners (scripts/mushra_listener.py) and for checking a test by hand:
  // what the current page plays behind each letter and whether the audio clock runs.
  // The stimulus files name their conditions anyway, so this reveals nothing a curious
  // listener could not find; a real listener has no reason to call it.
  window.mushraInspect = function () {
    const view = state.page;
    return {
      listener: state.listener,
      seed: state.seed,
      position: state.position,
      pages: state.pageOrder.length,
      finished: state.finished,
      page: view && {
        id: view.page.id,
        ready: view.ready,
        playing: view.playing,
        duration: view.duration,
        position: view.ready ? currentPosition(view) : 0,
        ready_after_s: view.readyAfter,
        loop: [view.loopStart, view.loopEnd],
        stimuli: view.stimuli.map((s) => ({letter: s.letter, condition: s.source.condition, played: s.played,
                                           rated: s.rated, value: Number(s.slider.value)})),
      },
      audio: audio.context && {state: audio.context.state, time: audio.context.currentTime,
                               sample_rate_hz: audio.context.sampleRate},
      scale: test.scale,
    };
  };

  init();
})();
