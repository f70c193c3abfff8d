// Tests of the C# binding against the built library: a console program (Debian's Mono has no test
// framework worth depending on) that runs each test, prints ok/FAILED per test and exits 1 on any
// failure. The scenario and layout files come from tests/bindings/run.sh (SSCAPE_SCENARIO_REFERENCE,
// SSCAPE_LAYOUTS); without them those two tests are skipped with a message.
using System;
using System.Collections.Generic;
using System.IO;
using System.Runtime.InteropServices;
using System.Threading;
using Sscape;
using Sscape.Native;

static class Tests
{
    static int failures;

    static void Run(string name, Action test)
    {
        try
        {
            test();
            Console.WriteLine("ok " + name);
        }
        catch (Exception e)
        {
            ++failures;
            Console.WriteLine("FAILED " + name + ": " + e);
        }
    }

    static void Assert(bool condition, string what)
    {
        if (!condition) throw new Exception("assertion failed: " + what);
    }

    static void Throws<T>(Action action, Func<T, bool> check, string what) where T : Exception
    {
        try { action(); }
        catch (T e)
        {
            Assert(check(e), what + " (" + e.Message + ")");
            return;
        }
        throw new Exception("no " + typeof(T).Name + ": " + what);
    }

    static void Add(List<byte> bytes, float[] values)
    {
        byte[] raw = new byte[values.Length * 4];
        Buffer.BlockCopy(values, 0, raw, 0, raw.Length);
        bytes.AddRange(raw);
    }

    // tests/bindings/scenario.c, step for step.
    static byte[] Scenario()
    {
        var bytes = new List<byte>();
        using (Model model = Model.LoadDefault())
        using (Body body = model.CreateBody())
        using (Fitter fitter = model.CreateFitter())
        {
            body.Shape = new float[] { 0.8f, -0.5f, 1.2f, 0.3f, -1.0f };
            float[] rotations = new float[model.JointCount * 4];
            for (int j = 0; j < model.JointCount; ++j) rotations[j * 4 + 3] = 1.0f;
            Array.Copy(new float[] { 0.0f, 0.0f, 0.25881904f, 0.96592583f }, 0, rotations, model.JointIndex("upperarm_l") * 4, 4);
            Array.Copy(new float[] { 0.0f, -0.17364818f, 0.0f, 0.98480775f }, 0, rotations, model.JointIndex("lowerarm_r") * 4, 4);
            body.SetPose(rotations, new float[] { 0.1f, 0.0f, -0.2f });
            Add(bytes, body.GetVertices());
            Add(bytes, body.Measure());
            float[] landmarks = body.GetLandmarks();
            Add(bytes, landmarks);
            fitter.AddLandmarks(model.LandmarkNames, landmarks);
            fitter.Solve();
            Pose pose = fitter.GetPose();
            Add(bytes, fitter.Shape);
            Add(bytes, pose.Rotations);
            Add(bytes, pose.Translation);
            Add(bytes, new float[] { pose.Scale });
            Add(bytes, model.Synthesize(model.SampleShapes(3, 7, 2.0f)));
        }
        return bytes.ToArray();
    }

    static void Main(string[] args)
    {
        // test.sh runs this again against a library of the next ABI major (a process loads one library).
        if (args.Length == 1 && args[0] == "--expect-abi-mismatch")
        {
            try { Model.LoadDefault(); }
            catch (SscapeException e)
            {
                bool refused = e.Status == ssc_status.SSC_ERROR_UNSUPPORTED_VERSION && e.Message.Contains("ABI major " + Library.AbiMajor);
                Console.WriteLine((refused ? "ok" : "FAILED") + " a library of another ABI major is refused: " + e.Message);
                Environment.Exit(refused ? 0 : 1);
            }
            Console.WriteLine("FAILED a library of another ABI major was used");
            Environment.Exit(1);
        }
        Run("the scenario gives the C API's bytes", delegate
        {
            string reference = Environment.GetEnvironmentVariable("SSCAPE_SCENARIO_REFERENCE");
            if (reference == null) { Console.WriteLine("skipped: SSCAPE_SCENARIO_REFERENCE not set (tests/bindings/run.sh sets it)"); return; }
            byte[] mine = Scenario(), theirs = File.ReadAllBytes(reference);
            Assert(mine.Length == theirs.Length, "sizes " + mine.Length + " and " + theirs.Length);
            for (int i = 0; i < mine.Length; ++i) Assert(mine[i] == theirs[i], "byte " + i + " differs");
        });

        Run("every struct is laid out as C lays it out", delegate
        {
            string layouts = Environment.GetEnvironmentVariable("SSCAPE_LAYOUTS");
            if (layouts == null) { Console.WriteLine("skipped: SSCAPE_LAYOUTS not set (tests/bindings/run.sh sets it)"); return; }
            foreach (string line in File.ReadAllLines(layouts))
            {
                string[] words = line.Split(' ');
                string[] what = words[0].Split('.');
                Type type = typeof(Api).Assembly.GetType("Sscape.Native." + what[0], true);
                long mine = what.Length == 1 ? Marshal.SizeOf(type) : (long)Marshal.OffsetOf(type, what[1]);
                Assert(mine == long.Parse(words[2]), line + ", C# says " + mine);
            }
        });

        Run("every function of the header is declared", delegate
        {
            string header = File.ReadAllText(Path.Combine(Environment.GetEnvironmentVariable("SSCAPE_SOURCE") ?? "../..", "include/sscape/sscape.h"));
            var inHeader = new SortedSet<string>();
            foreach (System.Text.RegularExpressions.Match m in System.Text.RegularExpressions.Regex.Matches(header,
                         @"^SSC_(?:API|EXPERIMENTAL)\s[^;(]*?\b(ssc_\w+)\s*\(", System.Text.RegularExpressions.RegexOptions.Multiline))
                inHeader.Add(m.Groups[1].Value);
            var declared = new SortedSet<string>();
            foreach (var method in typeof(Api).GetMethods())
                if (method.Name.StartsWith("ssc_")) declared.Add(method.Name);
            Assert(inHeader.SetEquals(declared), "declared " + declared.Count + ", in the header " + inHeader.Count);
        });

        Run("the library's ABI major is the binding's", delegate
        {
            Library.CheckAbi();
            Assert(Library.Version / 10000 == Library.AbiMajor, "version " + Library.Version);
            Assert(Library.VersionText == string.Format("{0}.{1}.{2}", Library.Version / 10000, Library.Version / 100 % 100, Library.Version % 100),
                   "version text " + Library.VersionText);
        });

        Run("errors become SscapeException with the status and message", delegate
        {
            foreach (ssc_status status in Enum.GetValues(typeof(ssc_status)))
                unsafe
                {
                    if (status == ssc_status.SSC_STATUS_FORCE32) continue;
                    string c = Library.Utf8(Api.ssc_status_name(status));
                    Assert(Library.StatusName(status) == c, status + " is " + c + " in C");
                }
            using (Model model = Model.LoadDefault())
            using (Body body = model.CreateBody())
            using (Fitter fitter = model.CreateFitter())
            {
                Throws<SscapeException>(() => model.JointIndex("no_such_joint"),
                    e => e.Status == ssc_status.SSC_ERROR_NOT_FOUND && e.Code == "SSC_ERROR_NOT_FOUND" && e.Message.Contains("no_such_joint"), "unknown joint");
                Throws<SscapeException>(() => body.Shape = new float[] { float.NaN },
                    e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "NaN shape");
                Throws<ArgumentException>(() => body.SetPose(new float[4]), e => true, "wrong rotation count");
                Throws<SscapeException>(() => body.GetVertices(new float[3]),
                    e => e.Status == ssc_status.SSC_ERROR_BUFFER_TOO_SMALL, "small buffer");
                Throws<SscapeException>(() => fitter.AddLandmarks(new[] { "Sellion", "Nonsense" }, new float[6]),
                    e => e.Status == ssc_status.SSC_ERROR_NOT_FOUND && e.Message.Contains("Nonsense"), "unknown landmark");
                ssc_fitter_def def = Model.DefaultFitterDef();
                def.shape_count = 1000000;
                Throws<SscapeException>(() => model.CreateFitter(def), e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "bad def");
                string dir = Path.Combine(Path.GetTempPath(), "sscape-cs-" + System.Diagnostics.Process.GetCurrentProcess().Id);
                Directory.CreateDirectory(dir);
                File.WriteAllText(Path.Combine(dir, "corrupt.sscape"), "SSCAPE not really a model");
                Throws<SscapeException>(() => Model.Load(Path.Combine(dir, "corrupt.sscape")), e => true, "corrupt model");
                Throws<SscapeException>(() => Model.Load(Path.Combine(dir, "missing.sscape")),
                    e => e.Status == ssc_status.SSC_ERROR_IO, "missing model");
                Throws<SscapeException>(() => Model.FromBytes(new byte[16]), e => true, "bytes that are no model");
                Directory.Delete(dir, true);
            }
            Body closed;
            using (Model model = Model.LoadDefault()) closed = model.CreateBody();
            closed.Dispose();
            closed.Dispose();  // idempotent
            Throws<ObjectDisposedException>(() => closed.GetVertices(), e => true, "use after Dispose");
        });

        Run("levels of detail: listed, posed, written one or all", delegate
        {
            using (Model model = Model.LoadDefault())
            using (Body body = model.CreateBody())
            {
                Level[] levels = model.Levels;
                Assert(levels.Length == 4 && levels[0].Name == "full" && levels[3].Name == "proxy741" && levels[3].VertexCount == 741, "four levels");
                int far = model.LevelIndex("proxy741");
                uint[] tris = model.LevelTriangles(far);
                Assert(tris.Length == levels[far].TriangleCount * 3, "the level's triangles");
                float[] v = body.GetLevelVertices(far);
                Assert(v.Length == 741 * 3 && !float.IsNaN(v[0]), "the level's vertices");
                float[] batch = model.Synthesize(new float[model.ShapeCount * 2], null, null, far);
                Assert(batch.Length == 2 * 741 * 3 && batch[741 * 3] == v[0], "many bodies of a level at once, as a body gives them");
                string dir = System.IO.Path.Combine(System.IO.Path.GetTempPath(), "sscape-cs-levels-" + System.Guid.NewGuid().ToString("N"));
                System.IO.Directory.CreateDirectory(dir);
                body.Write(System.IO.Path.Combine(dir, "all.glb"), Body.AllLevels);
                body.Write(System.IO.Path.Combine(dir, "morphs.glb"), Body.AllLevels, 4);
                body.Write(System.IO.Path.Combine(dir, "sliders.glb"), 0, Body.SliderMorphs);
                byte[] bytes = System.IO.File.ReadAllBytes(System.IO.Path.Combine(dir, "morphs.glb"));
                string json = System.Text.Encoding.ASCII.GetString(bytes, 20, BitConverter.ToInt32(bytes, 12));
                Assert(json.Contains("\"component_4\"") && json.Contains("sscape_morphs"), "morph targets and the joints' motion in the glb");
                Throws<SscapeException>(() => body.Write(System.IO.Path.Combine(dir, "x.obj"), 0, 2),
                    e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "morph targets are glTF only");
                Assert(new System.IO.FileInfo(System.IO.Path.Combine(dir, "all.glb")).Length > 1000000, "every level in one glb");
                Throws<SscapeException>(() => body.Write(System.IO.Path.Combine(dir, "all.obj"), Body.AllLevels),
                                        e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "all levels in an OBJ");
                System.IO.Directory.Delete(dir, true);
            }
        });

        Run("segment shape spaces: listed, set on a body, moving their part only", delegate
        {
            using (Model model = Model.LoadDefault())
            using (Body body = model.CreateBody())
            {
                Segment[] segments = model.Segments;
                Assert(segments.Length == 6 && segments[0].Name == "head" && segments[1].Name == "arm_l", "six segments, head first");
                int arm = model.SegmentIndex("arm_l");
                Assert(segments[arm].ShapeCount == 10 && segments[arm].VertexCount > 1000, "arm_l's counts");
                float[] before = body.GetVertices();
                body.SetSegmentShape(arm, new float[] { 2.0f });
                float[] shape = body.GetSegmentShape(arm, segments[arm].ShapeCount);
                Assert(shape[0] == 2.0f && shape[1] == 0.0f, "the coefficients read back");
                float[] after = body.GetVertices();
                double left = 0, right = 0;
                for (int v = 0; v < after.Length; v += 3)
                {
                    double dx = after[v] - before[v], dy = after[v + 1] - before[v + 1], dz = after[v + 2] - before[v + 2];
                    double d = Math.Sqrt(dx * dx + dy * dy + dz * dz);
                    if (before[v] > 0.3f) left = Math.Max(left, d);  // +X: the body's left
                    if (before[v] < -0.3f) right = Math.Max(right, d);
                }
                Assert(left > 0.005 && right == 0, "the left arm moves " + left + " m, the right " + right + " m");
                Throws<SscapeException>(() => model.SegmentIndex("tail"), e => e.Status == ssc_status.SSC_ERROR_NOT_FOUND, "unknown segment");
                Throws<SscapeException>(() => body.SetSegmentShape(arm, new float[11]), e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "too many");
                Throws<SscapeException>(() => body.SetSegmentShape(6, new float[1]), e => e.Status == ssc_status.SSC_ERROR_INVALID_ARGUMENT, "no segment 6");
            }
        });

        Run("a body outlives its model; a fit recovers a shape; callbacks cancel", delegate
        {
            Body body;
            using (Model model = Model.LoadDefault()) body = model.CreateBody();
            using (body)
            using (Model model = Model.LoadDefault())
            using (Fitter fitter = model.CreateFitter())
            {
                body.Shape = new float[] { 1.5f, -1.0f };
                float stature = body.Measure("stature");
                Assert(stature > 1.4f && stature < 2.1f, "stature " + stature);
                Assert(body.Measure().Length == Library.MeasurementNames.Length, "one value per measurement");
                fitter.AddLandmarks(model.LandmarkNames, body.GetLandmarks());
                ssc_fit_report report = fitter.Solve((i, cost) => false);
                Assert(report.iterations > 0 && report.landmark_rms < 0.01f, "rms " + report.landmark_rms);
                int calls = 0;
                Throws<SscapeException>(() => fitter.Solve((i, cost) => ++calls >= 2),
                    e => e.Status == ssc_status.SSC_ERROR_CANCELLED, "cancelled");
                Assert(calls == 2, "calls " + calls);
                Throws<InvalidOperationException>(() => fitter.Solve((i, cost) => { throw new InvalidOperationException("from the callback"); }),
                    e => e.Message == "from the callback", "a callback's exception comes back");
            }
        });

        Run("one model, many threads; the batch equals bodies made one by one", delegate
        {
            using (Model model = Model.LoadDefault())
            {
                float[] shapes = model.SampleShapes(4, 3);
                float[] batch = model.Synthesize(shapes);
                int k = model.ShapeCount, v = model.VertexCount * 3;
                var threads = new List<Thread>();
                var errors = new List<string>();
                for (int b = 0; b < 4; ++b)
                {
                    int index = b;
                    var thread = new Thread(() =>
                    {
                        using (Body body = model.CreateBody())
                        {
                            float[] shape = new float[k];
                            Array.Copy(shapes, index * k, shape, 0, k);
                            body.Shape = shape;
                            float[] vertices = body.GetVertices();
                            for (int i = 0; i < v; ++i)
                                if (vertices[i] != batch[index * v + i]) { lock (errors) errors.Add("body " + index); break; }
                        }
                    });
                    thread.Start();
                    threads.Add(thread);
                }
                foreach (Thread thread in threads) thread.Join();
                Assert(errors.Count == 0, string.Join(", ", errors));
            }
        });

        Run("undisposed objects are released by the finalizer", delegate
        {
            for (int i = 0; i < 50; ++i) Model.LoadDefault().CreateBody().GetVertices();
            GC.Collect();
            GC.WaitForPendingFinalizers();
        });

        Console.WriteLine(failures == 0 ? "all passed" : failures + " FAILED");
        Environment.Exit(failures == 0 ? 0 : 1);
    }
}
