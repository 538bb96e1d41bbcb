// Compiles a job with a Flamenco job type as Flamenco's Manager does, as far as
// tests/farm needs it, and prints the job's tasks as JSON:
//
//   node flamenco_compile.js JOB_TYPE.js 'SETTINGS_JSON'
//
// The Manager runs job types in its own JavaScript engine with these globals;
// frameChunker here follows its documented behaviour (Flamenco's js_globals.go):
// the frames of "A-B, C" (or "A..B") sorted and split into chunks of at most
// `size` frames, each written back as "A-B" runs, two neighbours as "A,B".
"use strict";
const fs = require("fs");
const vm = require("vm");

function explode(range) {
  const frames = new Set();
  for (const part of range.replaceAll("..", "-").split(",")) {
    const [start, end] = part.split("-").map((text) => parseInt(text.trim(), 10));
    for (let frame = start; frame <= (end === undefined ? start : end); frame++) {
      frames.add(frame);
    }
  }
  return [...frames].sort((a, b) => a - b);
}

function merge(frames) {
  const runs = [];
  let start = frames[0];
  for (let i = 1; i <= frames.length; i++) {
    if (i === frames.length || frames[i] !== frames[i - 1] + 1) {
      const end = frames[i - 1];
      if (start === end) runs.push(`${start}`);
      else if (start + 1 === end) runs.push(`${start}`, `${end}`);
      else runs.push(`${start}-${end}`);
      start = frames[i];
    }
  }
  return runs.join(",");
}

function frameChunker(range, size) {
  const frames = explode(range);
  const chunks = [];
  for (let i = 0; i < frames.length; i += size) {
    chunks.push(merge(frames.slice(i, i + size)));
  }
  return chunks;
}

const [script, settings] = process.argv.slice(2);
const context = {
  author: {
    Task: (name, type) => ({
      name,
      type,
      commands: [],
      addCommand(command) {
        this.commands.push(command);
      },
    }),
    Command: (name, parameters) => ({ name, parameters }),
  },
  frameChunker,
  formatTimestampLocal: () => "2024-01-02_030405",
  print: () => {},
};
vm.createContext(context);
vm.runInContext(fs.readFileSync(script, "utf8"), context);
const job = {
  settings: JSON.parse(settings),
  created: new Date(),
  tasks: [],
  addTask(task) {
    this.tasks.push(task);
  },
};
context.job = job;
vm.runInContext("compileJob(job)", context);
console.log(JSON.stringify({ settings: job.settings, tasks: job.tasks }));
