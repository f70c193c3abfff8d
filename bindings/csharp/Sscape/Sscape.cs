// sscape for C# (Mono and .NET): Model, Body and Fitter over the C library, whose handles are
// SafeHandles (released by Dispose or, failing that, by the finalizer). A body or fitter keeps its
// model alive in C, so they may be disposed in any order. A failed call throws SscapeException with
// the C status and the library's message. Units: metres and kilograms; right-handed, Y up, the body
// facing +Z; quaternions x y z w. The raw declarations are Sscape.Native.Api (Native.g.cs);
// include/sscape/sscape.h documents every function.
//
// Written for C# 6 as Debian's Mono compiles it (mcs): arrays rather than Span<T> (Mono has no
// System.Memory), IntPtr/UIntPtr rather than nint/nuint, delegates rather than function pointers,
// no tuples, records, switch expressions or 'using var'. The same code builds on .NET.
using System;
using System.Runtime.InteropServices;
using System.Text;
using Sscape.Native;

namespace Sscape
{
    /// <summary>A failed call of the C library.</summary>
    public class SscapeException : Exception
    {
        /// <summary>The ssc_status value (negative).</summary>
        public ssc_status Status { get; private set; }

        /// <summary>The status's name, e.g. "SSC_ERROR_NOT_FOUND".</summary>
        public string Code { get; private set; }

        public SscapeException(ssc_status status, string message)
            : base(Library.StatusName(status) + ": " + message)
        {
            Status = status;
            Code = Library.StatusName(status);
        }
    }

    /// <summary>The loaded C library: its version, and the checks every call goes through.</summary>
    public static unsafe class Library
    {
        /// <summary>The C API major version this binding is written for; the loaded library must have the same.</summary>
        public const uint AbiMajor = Api.SSC_VERSION_MAJOR;

        static bool abiChecked;

        /// <summary>The loaded library's version number (major * 10000 + minor * 100 + patch).</summary>
        public static uint Version { get { return Api.ssc_version(); } }

        /// <summary>The loaded library's version as people write it: "0.1.0".</summary>
        public static string VersionText { get { return Text(Api.ssc_version()); } }

        static string Text(uint number) { return string.Format("{0}.{1}.{2}", number / 10000, number / 100 % 100, number % 100); }

        /// <summary>Throws unless the loaded library's ABI major is this binding's.</summary>
        public static void CheckAbi()
        {
            if (abiChecked) return;
            uint version = Api.ssc_version();
            if (version / 10000 != AbiMajor)
                throw new SscapeException(ssc_status.SSC_ERROR_UNSUPPORTED_VERSION, string.Format(
                    "the loaded libsscape is version {0}; this binding is for ABI major {1}", Text(version), AbiMajor));
            abiChecked = true;
        }

        /// <summary>The status's name as C spells it (the enum's own, so it works before the ABI check too).</summary>
        public static string StatusName(ssc_status status)
        {
            return Enum.IsDefined(typeof(ssc_status), status) ? status.ToString() : "SSC_ERROR_UNKNOWN(" + (int)status + ")";
        }

        /// <summary>Throws SscapeException with ssc_last_error's message unless status is SSC_OK.</summary>
        public static void Check(ssc_status status)
        {
            if (status != ssc_status.SSC_OK) throw new SscapeException(status, Utf8(Api.ssc_last_error()));
        }

        /// <summary>A NUL-terminated UTF-8 string (owned by the library) as a string.</summary>
        public static string Utf8(byte* text)
        {
            if (text == null) return null;
            int length = 0;
            while (text[length] != 0) ++length;
            return Encoding.UTF8.GetString(text, length);
        }

        /// <summary>A string as NUL-terminated UTF-8, to pin with fixed.</summary>
        public static byte[] ToUtf8(string text)
        {
            if (text == null) throw new ArgumentNullException("text");
            if (text.IndexOf('\0') >= 0) throw new ArgumentException("contains a NUL character", "text");
            byte[] bytes = new byte[Encoding.UTF8.GetByteCount(text) + 1];
            Encoding.UTF8.GetBytes(text, 0, text.Length, bytes, 0);
            return bytes;
        }

        internal static void Count(float[] values, int expected, string name)
        {
            if (values == null) throw new ArgumentNullException(name);
            if (values.Length != expected)
                throw new ArgumentException(string.Format("{0} values where {1} are needed", values.Length, expected), name);
        }

        /// <summary>The measurements the library knows, in the order of Body.Measure().</summary>
        public static string[] MeasurementNames
        {
            get
            {
                string[] names = new string[Api.ssc_measurement_count()];
                for (uint i = 0; i < names.Length; ++i)
                {
                    byte* name, definition;
                    ssc_unit unit;
                    Check(Api.ssc_measurement_get_info(i, &name, &unit, &definition));
                    names[i] = Utf8(name);
                }
                return names;
            }
        }
    }

    /// <summary>An ssc_model reference.</summary>
    public sealed class ModelHandle : SafeHandle
    {
        public ModelHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Api.ssc_model_release(handle); return true; }
        internal void Set(IntPtr value) { SetHandle(value); }
    }

    /// <summary>An ssc_body.</summary>
    public sealed class BodyHandle : SafeHandle
    {
        public BodyHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Api.ssc_body_destroy(handle); return true; }
        internal void Set(IntPtr value) { SetHandle(value); }
    }

    /// <summary>An ssc_fitter.</summary>
    public sealed class FitterHandle : SafeHandle
    {
        public FitterHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Api.ssc_fitter_destroy(handle); return true; }
        internal void Set(IntPtr value) { SetHandle(value); }
    }

    /// <summary>A segment shape space: its name, components and the vertices they move.</summary>
    public struct Segment
    {
        public string Name;
        public int ShapeCount, VertexCount;
    }

    /// <summary>A level of detail: 0 the full mesh ("full"), then the model's coarser meshes, finest first.</summary>
    public struct Level
    {
        public int Index;
        public string Name;
        public int VertexCount, TriangleCount, UvCount;
    }

    /// <summary>The counts a body or fitter needs of its model, read once.</summary>
    internal struct Counts
    {
        public int Vertices, Joints, Shapes, Landmarks;
        public int[] LevelVertices;
    }

    /// <summary>A loaded model: immutable, safe to share across threads.</summary>
    public sealed unsafe class Model : IDisposable
    {
        readonly ModelHandle handle;

        /// <summary>The handle, for calls through Sscape.Native.Api.</summary>
        public ModelHandle Handle { get { return handle; } }

        Model(IntPtr raw)
        {
            handle = new ModelHandle();
            handle.Set(raw);
        }

        /// <summary>The default model built into the library.</summary>
        public static Model LoadDefault()
        {
            Library.CheckAbi();
            IntPtr raw;
            Library.Check(Api.ssc_model_load_default(IntPtr.Zero, &raw));
            return new Model(raw);
        }

        /// <summary>A .sscape file, verified before use.</summary>
        public static Model Load(string path)
        {
            Library.CheckAbi();
            byte[] utf8 = Library.ToUtf8(path);
            IntPtr raw;
            fixed (byte* p = utf8) Library.Check(Api.ssc_model_load_file(IntPtr.Zero, p, &raw));
            return new Model(raw);
        }

        /// <summary>A .sscape file's bytes (copied).</summary>
        public static Model FromBytes(byte[] bytes)
        {
            Library.CheckAbi();
            if (bytes == null) throw new ArgumentNullException("bytes");
            IntPtr raw;
            fixed (byte* p = bytes) Library.Check(Api.ssc_model_load_memory(IntPtr.Zero, p, (UIntPtr)bytes.Length, &raw));
            return new Model(raw);
        }

        public void Dispose() { handle.Dispose(); }

        IntPtr Raw
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Model");
                return handle.DangerousGetHandle();
            }
        }

        public int VertexCount { get { int n = (int)Api.ssc_model_vertex_count(Raw); GC.KeepAlive(this); return n; } }
        public int TriangleCount { get { int n = (int)Api.ssc_model_triangle_count(Raw); GC.KeepAlive(this); return n; } }
        public int JointCount { get { int n = (int)Api.ssc_model_joint_count(Raw); GC.KeepAlive(this); return n; } }
        public int ShapeCount { get { int n = (int)Api.ssc_model_shape_count(Raw); GC.KeepAlive(this); return n; } }
        public int LandmarkCount { get { int n = (int)Api.ssc_model_landmark_count(Raw); GC.KeepAlive(this); return n; } }

        internal Counts Counts
        {
            get
            {
                Level[] levels = Levels;
                int[] levelVertices = new int[levels.Length];
                for (int i = 0; i < levels.Length; ++i) levelVertices[i] = levels[i].VertexCount;
                return new Counts { Vertices = VertexCount, Joints = JointCount, Shapes = ShapeCount, Landmarks = LandmarkCount, LevelVertices = levelVertices };
            }
        }

        /// <summary>3 vertex indices per triangle.</summary>
        public uint[] Triangles
        {
            get
            {
                uint[] out_ = new uint[TriangleCount * 3];
                fixed (uint* p = out_) Library.Check(Api.ssc_model_get_triangles(Raw, p, (uint)TriangleCount));
                GC.KeepAlive(this);
                return out_;
            }
        }

        /// <summary>Joint names, in joint order.</summary>
        public string[] JointNames
        {
            get
            {
                string[] names = new string[JointCount];
                for (uint i = 0; i < names.Length; ++i)
                {
                    byte* name;
                    Library.Check(Api.ssc_model_get_joint_name(Raw, i, &name));
                    names[i] = Library.Utf8(name);
                }
                GC.KeepAlive(this);
                return names;
            }
        }

        /// <summary>Landmark names (CAESAR names in the default model), in landmark order.</summary>
        public string[] LandmarkNames
        {
            get
            {
                string[] names = new string[LandmarkCount];
                for (uint i = 0; i < names.Length; ++i)
                {
                    byte* name;
                    Library.Check(Api.ssc_model_get_landmark_name(Raw, i, &name));
                    names[i] = Library.Utf8(name);
                }
                GC.KeepAlive(this);
                return names;
            }
        }

        /// <summary>A joint's index; SSC_ERROR_NOT_FOUND for an unknown name.</summary>
        public int JointIndex(string name) { return Find(Api.ssc_model_find_joint, name); }

        /// <summary>A landmark's index; SSC_ERROR_NOT_FOUND for an unknown name.</summary>
        public int LandmarkIndex(string name) { return Find(Api.ssc_model_find_landmark, name); }

        unsafe delegate ssc_status Finder(IntPtr model, byte* name, uint* index);

        // One of the C API's find-by-name calls (joint, landmark, segment).
        int Find(Finder find, string name)
        {
            byte[] utf8 = Library.ToUtf8(name);
            uint index;
            fixed (byte* p = utf8) Library.Check(find(Raw, p, &index));
            GC.KeepAlive(this);
            return (int)index;
        }

        /// <summary>The segment shape spaces (head, arm_l, ...; none in a model without them), in index order.</summary>
        public Segment[] Segments
        {
            get
            {
                Segment[] segments = new Segment[Api.ssc_model_segment_count(Raw)];
                for (uint i = 0; i < segments.Length; ++i)
                {
                    ssc_segment_info info = new ssc_segment_info { struct_size = (uint)sizeof(ssc_segment_info) };
                    Library.Check(Api.ssc_model_get_segment_info(Raw, i, &info));
                    segments[i] = new Segment { Name = Library.Utf8(info.name), ShapeCount = (int)info.shape_count, VertexCount = (int)info.vertex_count };
                }
                GC.KeepAlive(this);
                return segments;
            }
        }

        /// <summary>A segment's index; SSC_ERROR_NOT_FOUND for a name the model lacks.</summary>
        public int SegmentIndex(string name) { return Find(Api.ssc_model_find_segment, name); }

        /// <summary>The levels of detail, in index order: 0 the full mesh, then the model's, finest first.</summary>
        public Level[] Levels
        {
            get
            {
                Level[] levels = new Level[Api.ssc_model_level_count(Raw)];
                for (uint i = 0; i < levels.Length; ++i)
                {
                    ssc_level_info info = new ssc_level_info { struct_size = (uint)sizeof(ssc_level_info) };
                    Library.Check(Api.ssc_model_get_level_info(Raw, i, &info));
                    levels[i] = new Level { Index = (int)i, Name = Library.Utf8(info.name), VertexCount = (int)info.vertex_count,
                                            TriangleCount = (int)info.triangle_count, UvCount = (int)info.uv_count };
                }
                GC.KeepAlive(this);
                return levels;
            }
        }

        /// <summary>A level's index by name; ArgumentException for a name the model lacks.</summary>
        public int LevelIndex(string name)
        {
            foreach (Level l in Levels)
                if (l.Name == name) return l.Index;
            throw new ArgumentException("the model has no level '" + name + "'", "name");
        }

        /// <summary>A level's triangles, 3 vertex indices each.</summary>
        public uint[] LevelTriangles(int level)
        {
            if (level < 0) throw new ArgumentOutOfRangeException("level");
            ssc_level_info info = new ssc_level_info { struct_size = (uint)sizeof(ssc_level_info) };
            Library.Check(Api.ssc_model_get_level_info(Raw, (uint)level, &info));
            uint[] out_ = new uint[info.triangle_count * 3];
            fixed (uint* p = out_) Library.Check(Api.ssc_model_get_level_triangles(Raw, (uint)level, p, info.triangle_count));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>count * ShapeCount coefficients of random bodies of the population, reproducible by seed.</summary>
        public float[] SampleShapes(int count, uint seed = 1, float truncation = 2.5f)
        {
            if (count < 0) throw new ArgumentOutOfRangeException("count");
            float[] out_ = new float[count * ShapeCount];
            fixed (float* p = out_)
                Library.Check(Api.ssc_model_sample_shapes(Raw, seed, (uint)count, truncation, p, (uint)out_.Length));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>
        /// Many bodies in one call: shapes holds count * ShapeCount coefficients; poses (or null: the
        /// rest pose) count * JointCount quaternions; translations (or null) count * 3. Returns
        /// count * VertexCount * 3 vertex coordinates, body after body. With a level of detail (Levels),
        /// its vertices: count * that level's VertexCount * 3.
        /// </summary>
        public float[] Synthesize(float[] shapes, float[] poses = null, float[] translations = null, int level = 0)
        {
            Level[] levels = Levels;
            if (level < 0 || level >= levels.Length) throw new ArgumentOutOfRangeException("level");
            int n = levels[level].VertexCount;
            if (shapes == null) throw new ArgumentNullException("shapes");
            int k = ShapeCount, count = k == 0 ? 0 : shapes.Length / k;
            if (k == 0 || shapes.Length % k != 0)
                throw new ArgumentException(shapes.Length + " coefficients are not a whole number of bodies", "shapes");
            if (poses != null) Library.Count(poses, count * JointCount * 4, "poses");
            if (translations != null) Library.Count(translations, count * 3, "translations");
            float[] vertices = new float[count * n * 3];
            ssc_batch_desc desc;
            Api.ssc_batch_desc_init(&desc, (UIntPtr)sizeof(ssc_batch_desc));
            desc.level = (uint)level;
            fixed (float* s = shapes, r = poses, t = translations, v = vertices)
            {
                desc.body_count = (uint)count;
                desc.shapes = s;
                desc.shape_count = (uint)k;
                desc.poses = r;
                desc.translations = t;
                desc.vertices = v;
                desc.vertices_capacity = (UIntPtr)(count * n);
                Library.Check(Api.ssc_model_synthesize_batch(Raw, &desc));
            }
            GC.KeepAlive(this);
            return vertices;
        }

        /// <summary>A new body of this model: mean shape, rest pose.</summary>
        public Body CreateBody()
        {
            IntPtr raw;
            Library.Check(Api.ssc_body_create(Raw, null, &raw));
            GC.KeepAlive(this);
            return new Body(raw, Counts);
        }

        /// <summary>The fitter's settings with their defaults, to change and pass to CreateFitter.</summary>
        public static ssc_fitter_def DefaultFitterDef()
        {
            ssc_fitter_def def;
            Api.ssc_fitter_def_init(&def, (UIntPtr)sizeof(ssc_fitter_def));
            return def;
        }

        /// <summary>A new fitter with the default settings.</summary>
        public Fitter CreateFitter()
        {
            return CreateFitter(DefaultFitterDef());
        }

        /// <summary>A new fitter with the given settings (from DefaultFitterDef).</summary>
        public Fitter CreateFitter(ssc_fitter_def def)
        {
            IntPtr raw;
            Library.Check(Api.ssc_fitter_create(Raw, &def, &raw));
            GC.KeepAlive(this);
            return new Fitter(raw, Counts);
        }
    }

    /// <summary>One body: shape and pose in, vertices and measurements out. One thread at a time.</summary>
    public sealed unsafe class Body : IDisposable
    {
        readonly BodyHandle handle;
        readonly Counts counts;

        /// <summary>The handle, for calls through Sscape.Native.Api.</summary>
        public BodyHandle Handle { get { return handle; } }

        internal Body(IntPtr raw, Counts counts)
        {
            handle = new BodyHandle();
            handle.Set(raw);
            this.counts = counts;
        }

        public void Dispose() { handle.Dispose(); }

        IntPtr Raw
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Body");
                return handle.DangerousGetHandle();
            }
        }

        /// <summary>The shape coefficients; setting n of them sets the rest to 0.</summary>
        public float[] Shape
        {
            get
            {
                float[] out_ = new float[counts.Shapes];
                fixed (float* p = out_) Library.Check(Api.ssc_body_get_shape(Raw, p, (uint)out_.Length));
                GC.KeepAlive(this);
                return out_;
            }
            set
            {
                if (value == null) throw new ArgumentNullException("value");
                fixed (float* p = value) Library.Check(Api.ssc_body_set_shape(Raw, p, (uint)value.Length));
                GC.KeepAlive(this);
            }
        }

        /// <summary>One segment's coefficients (Model.SegmentIndex), on top of the whole-body shape;
        /// setting n of them sets the segment's rest to 0.</summary>
        public void SetSegmentShape(int segment, float[] coefficients)
        {
            if (coefficients == null) throw new ArgumentNullException("coefficients");
            if (segment < 0) throw new ArgumentOutOfRangeException("segment");
            fixed (float* p = coefficients) Library.Check(Api.ssc_body_set_segment_shape(Raw, (uint)segment, p, (uint)coefficients.Length));
            GC.KeepAlive(this);
        }

        /// <summary>One segment's coefficients (its Segment.ShapeCount of them).</summary>
        public float[] GetSegmentShape(int segment, int shapeCount)
        {
            if (segment < 0) throw new ArgumentOutOfRangeException("segment");
            float[] out_ = new float[shapeCount];
            fixed (float* p = out_) Library.Check(Api.ssc_body_get_segment_shape(Raw, (uint)segment, p, (uint)out_.Length));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>JointCount quaternions (x y z w, relative to the parent; null: the rest pose) and a translation (or null).</summary>
        public void SetPose(float[] rotations, float[] translation = null)
        {
            if (rotations != null) Library.Count(rotations, counts.Joints * 4, "rotations");
            if (translation != null) Library.Count(translation, 3, "translation");
            fixed (float* r = rotations, t = translation)
                Library.Check(Api.ssc_body_set_pose(Raw, r, rotations == null ? 0u : (uint)counts.Joints, t));
            GC.KeepAlive(this);
        }

        /// <summary>The posed vertices (VertexCount * 3, metres), into a new array.</summary>
        public float[] GetVertices()
        {
            float[] out_ = new float[counts.Vertices * 3];
            GetVertices(out_);
            return out_;
        }

        /// <summary>The posed vertices into the caller's array (at least VertexCount * 3), e.g. to reuse it every frame.</summary>
        public void GetVertices(float[] destination)
        {
            if (destination == null) throw new ArgumentNullException("destination");
            fixed (float* p = destination)
                Library.Check(Api.ssc_body_get_vertices(Raw, p, (uint)(destination.Length / 3), UIntPtr.Zero));
            GC.KeepAlive(this);
        }

        /// <summary>Unit normals of the posed body (VertexCount * 3).</summary>
        public float[] GetNormals()
        {
            float[] out_ = new float[counts.Vertices * 3];
            fixed (float* p = out_) Library.Check(Api.ssc_body_get_normals(Raw, p, (uint)counts.Vertices, UIntPtr.Zero));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>The model's landmarks on the posed body (LandmarkCount * 3).</summary>
        public float[] GetLandmarks()
        {
            float[] out_ = new float[counts.Landmarks * 3];
            fixed (float* p = out_) Library.Check(Api.ssc_body_get_landmarks(Raw, p, (uint)counts.Landmarks, UIntPtr.Zero));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>Every measurement, in the order of Library.MeasurementNames.</summary>
        public float[] Measure()
        {
            float[] out_ = new float[Api.ssc_measurement_count()];
            fixed (float* p = out_) Library.Check(Api.ssc_body_measure(Raw, p, (uint)out_.Length));
            GC.KeepAlive(this);
            return out_;
        }

        /// <summary>One measurement by name ("stature", "waist_girth", ...).</summary>
        public float Measure(string name)
        {
            byte[] utf8 = Library.ToUtf8(name);
            float value;
            fixed (byte* p = utf8) Library.Check(Api.ssc_body_measure_by_name(Raw, p, &value));
            GC.KeepAlive(this);
            return value;
        }

        /// <summary>Writes the posed body as OBJ, PLY or glTF binary, chosen by the file's extension.</summary>
        public void Write(string path) { Write(path, 0); }

        /// <summary>Write's level for every level of detail in one .glb file (a node each).</summary>
        public const int AllLevels = -1;

        /// <summary>Writes a level of detail of the posed body (0 the full mesh; AllLevels: every level in one .glb).</summary>
        public void Write(string path, int level)
        {
            if (level < AllLevels) throw new ArgumentOutOfRangeException("level");
            byte[] utf8 = Library.ToUtf8(path);
            fixed (byte* p = utf8)
                Library.Check(Api.ssc_body_write_level_file(Raw, level == AllLevels ? 0xFFFFFFFFu : (uint)level, p, ssc_file_format.SSC_FILE_FORMAT_BY_EXTENSION));
            GC.KeepAlive(this);
        }

        /// <summary>Write's morphs for the semantic sliders as morph targets instead of components.</summary>
        public const int SliderMorphs = -1;

        /// <summary>
        /// Writes a .glb for engines: a level (or AllLevels) with shape morph targets, the first morphs
        /// components (weight 1 = +1 SD) or SliderMorphs (one per semantic slider); the joints' motion
        /// per unit of weight is in the file's skins[0].extras.sscape_morphs (docs/engines.md).
        /// </summary>
        public void Write(string path, int level, int morphs)
        {
            if (level < AllLevels) throw new ArgumentOutOfRangeException("level");
            if (morphs < SliderMorphs) throw new ArgumentOutOfRangeException("morphs");
            ssc_export_def def;
            Api.ssc_export_def_init(&def, (UIntPtr)sizeof(ssc_export_def));
            def.level = level == AllLevels ? 0xFFFFFFFFu : (uint)level;
            if (morphs == SliderMorphs) def.morphs = ssc_morphs.SSC_MORPHS_SLIDERS;
            else if (morphs > 0) { def.morphs = ssc_morphs.SSC_MORPHS_COMPONENTS; def.morph_count = (uint)morphs; }
            byte[] utf8 = Library.ToUtf8(path);
            fixed (byte* p = utf8) Library.Check(Api.ssc_body_export(Raw, p, &def));
            GC.KeepAlive(this);
        }

        /// <summary>A level of detail's posed vertices (its VertexCount * 3, metres).</summary>
        public float[] GetLevelVertices(int level)
        {
            if (level < 0 || level >= counts.LevelVertices.Length) throw new ArgumentOutOfRangeException("level");
            int n = counts.LevelVertices[level];
            float[] out_ = new float[n * 3];
            fixed (float* p = out_) Library.Check(Api.ssc_body_get_level_vertices(Raw, (uint)level, p, (uint)n, UIntPtr.Zero));
            GC.KeepAlive(this);
            return out_;
        }
    }

    /// <summary>A fitted pose: JointCount quaternions, the root translation and the scale.</summary>
    public sealed class Pose
    {
        public float[] Rotations;
        public float[] Translation;
        public float Scale;
    }

    /// <summary>Fits shape and pose to landmarks and scan points. One thread at a time.</summary>
    public sealed unsafe class Fitter : IDisposable
    {
        readonly FitterHandle handle;
        readonly Counts counts;

        /// <summary>The handle, for calls through Sscape.Native.Api.</summary>
        public FitterHandle Handle { get { return handle; } }

        internal Fitter(IntPtr raw, Counts counts)
        {
            handle = new FitterHandle();
            handle.Set(raw);
            this.counts = counts;
        }

        public void Dispose() { handle.Dispose(); }

        IntPtr Raw
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Fitter");
                return handle.DangerousGetHandle();
            }
        }

        /// <summary>Landmarks of a frame by name, positions names.Length * 3 (metres), weights optional.</summary>
        public void AddLandmarks(string[] names, float[] positions, float[] weights = null, uint frame = 0)
        {
            if (names == null) throw new ArgumentNullException("names");
            Library.Count(positions, names.Length * 3, "positions");
            if (weights != null) Library.Count(weights, names.Length, "weights");
            GCHandle[] pins = new GCHandle[names.Length];
            IntPtr[] pointers = new IntPtr[names.Length];
            try
            {
                for (int i = 0; i < names.Length; ++i)
                {
                    pins[i] = GCHandle.Alloc(Library.ToUtf8(names[i]), GCHandleType.Pinned);
                    pointers[i] = pins[i].AddrOfPinnedObject();
                }
                fixed (IntPtr* n = pointers)
                fixed (float* p = positions, w = weights)
                    Library.Check(Api.ssc_fitter_add_landmarks_by_name(Raw, frame, (byte**)n, p, w, (uint)names.Length));
            }
            finally
            {
                foreach (GCHandle pin in pins)
                    if (pin.IsAllocated) pin.Free();
            }
            GC.KeepAlive(this);
        }

        /// <summary>Scan points of a frame (count * 3, metres), with normals (count * 3) or null.</summary>
        public void AddPoints(float[] points, float[] normals = null, uint frame = 0)
        {
            if (points == null) throw new ArgumentNullException("points");
            if (points.Length % 3 != 0) throw new ArgumentException("not whole points", "points");
            if (normals != null) Library.Count(normals, points.Length, "normals");
            fixed (float* p = points, n = normals)
                Library.Check(Api.ssc_fitter_add_points(Raw, frame, p, n, null, (uint)(points.Length / 3), UIntPtr.Zero));
            GC.KeepAlive(this);
        }

        /// <summary>
        /// Solves. progress(iteration, cost) is called each iteration; returning true cancels
        /// (SscapeException with SSC_ERROR_CANCELLED). Non-convergence is in the report, not an error.
        /// </summary>
        public ssc_fit_report Solve(Func<uint, float, bool> progress = null)
        {
            ssc_fit_report report = new ssc_fit_report();
            report.struct_size = (uint)sizeof(ssc_fit_report);
            ssc_progress_fn callback = null;
            Exception thrown = null;
            IntPtr function = IntPtr.Zero;
            if (progress != null)
            {
                // An exception must not cross the C frames: it cancels and is thrown again here.
                callback = delegate (void* user, uint iteration, float cost)
                {
                    try { return progress(iteration, cost) ? 1 : 0; }
                    catch (Exception e) { thrown = e; return 1; }
                };
                function = Marshal.GetFunctionPointerForDelegate(callback);
            }
            ssc_status status = Api.ssc_fitter_solve(Raw, function, null, &report);
            GC.KeepAlive(callback);  // alive until the C side is done with it
            GC.KeepAlive(this);
            if (thrown != null) throw thrown;
            Library.Check(status);
            return report;
        }

        /// <summary>The fitted shape coefficients.</summary>
        public float[] Shape
        {
            get
            {
                float[] out_ = new float[counts.Shapes];
                fixed (float* p = out_) Library.Check(Api.ssc_fitter_get_shape(Raw, p, (uint)out_.Length));
                GC.KeepAlive(this);
                return out_;
            }
        }

        /// <summary>The fitted pose of a frame.</summary>
        public Pose GetPose(uint frame = 0)
        {
            Pose pose = new Pose { Rotations = new float[counts.Joints * 4], Translation = new float[3] };
            float scale;
            fixed (float* r = pose.Rotations, t = pose.Translation)
                Library.Check(Api.ssc_fitter_get_pose(Raw, frame, r, (uint)counts.Joints, t, &scale));
            pose.Scale = scale;
            GC.KeepAlive(this);
            return pose;
        }

        /// <summary>The fitted body's vertices in a frame (VertexCount * 3).</summary>
        public float[] GetVertices(uint frame = 0)
        {
            float[] out_ = new float[counts.Vertices * 3];
            fixed (float* p = out_)
                Library.Check(Api.ssc_fitter_get_vertices(Raw, frame, p, (uint)counts.Vertices, UIntPtr.Zero));
            GC.KeepAlive(this);
            return out_;
        }
    }
}
