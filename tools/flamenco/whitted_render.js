// A Flamenco 3 job type that renders Whitted frames in chunks: one Blender start
// per chunk, and a failed Whitted frame fails its task (exit code 3), which
// Blender's own exit code would not say (docs/FARM.md, "Farms we do not drive").
//
// Install: copy this file into the folder `scripts/` beside the flamenco-manager
// executable and restart the Manager; "Whitted Render" joins the job types. Workers
// need Blender with the Whitted add-on enabled in their user preferences.
//
// Each task runs, through Flamenco's blender-render command:
//   {blender} {blenderArgs} FILE -E WHITTED --python-expr EXIT_ON_ERROR
//       --render-output PATH --render-format FORMAT --render-frame CHUNK
// EXIT_ON_ERROR sets WHITTED_EXIT_ON_ERROR=1 inside that Blender, so a frame
// Whitted cannot render ends Blender at once with exit code 3 and no image: the
// task fails, and Flamenco retries it or reports it.

const JOB_TYPE = {
  label: "Whitted Render",
  description: "Render a frame range with Whitted, several frames per Blender start",
  settings: [
    {
      key: "frames",
      type: "string",
      required: true,
      eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
      evalInfo: { showLinkButton: true, description: "Scene frame range" },
      description: "Frames to render, like '1-240' or '1-10, 20'",
    },
    {
      key: "chunk_size",
      type: "int32",
      default: 20,
      propargs: { min: 1 },
      visible: "submission",
      description:
        "Frames per task (one Blender start each): a Whitted frame often renders in " +
        "less time than Blender takes to start, so chunks of many frames pay off",
    },
    {
      key: "render_output_root",
      type: "string",
      subtype: "dir_path",
      required: true,
      visible: "submission",
      description: "Folder the job's own output folder is made in",
    },
    {
      key: "add_path_components",
      type: "int32",
      required: true,
      default: 0,
      propargs: { min: 0, max: 32 },
      visible: "submission",
      description: "How many folders of the blend file's path to repeat under the root",
    },
    {
      key: "render_output_path",
      type: "string",
      subtype: "file_path",
      editable: false,
      eval:
        "str(Path(abspath(settings.render_output_root), " +
        "last_n_dir_parts(settings.add_path_components), jobname, '{timestamp}', '######'))",
      description: "Where the frames are written",
    },
    {
      key: "blendfile",
      type: "string",
      required: true,
      visible: "web",
      description: "The blend file to render",
    },
    {
      key: "format",
      type: "string",
      required: true,
      eval: "C.scene.render.image_settings.file_format",
      visible: "web",
    },
  ],
};

// Run inside Blender before it renders: the engine reads this at its first failure.
const EXIT_ON_ERROR = "import os; os.environ['WHITTED_EXIT_ON_ERROR'] = '1'";

function compileJob(job) {
  const settings = job.settings;
  const output = settings.render_output_path.replace("{timestamp}", () =>
    formatTimestampLocal(job.created),
  );
  settings.render_output_path = output; // the job shows the path its frames went to
  for (const chunk of frameChunker(settings.frames, settings.chunk_size)) {
    job.addTask(renderTask(settings, output, chunk));
  }
}

// One task: one Blender renders the frames of `chunk` ("1-20", "7", "3,4", ...).
function renderTask(settings, output, chunk) {
  const task = author.Task(`render-${chunk}`, "blender");
  task.addCommand(
    author.Command("blender-render", {
      exe: "{blender}",
      exeArgs: "{blenderArgs}",
      argsBefore: [],
      blendfile: settings.blendfile,
      args: [
        // After the file: the engine of the scene it loaded.
        "-E",
        "WHITTED",
        "--python-expr",
        EXIT_ON_ERROR,
        "--render-output",
        output,
        "--render-format",
        settings.format,
        // Blender's notation for a range is A..B.
        "--render-frame",
        chunk.replaceAll("-", ".."),
      ],
    }),
  );
  return task;
}
